//! Test rig for Part 4 groups and the platform profile (plcopen_platform.md): an engine with
//! axes x, y, z, stepping by hand at 1 ms, helpers for group and platform calls.
#![allow(dead_code)]

use axis_engine::group::*;
use axis_engine::platform::raw;
use axis_engine::platform::*;
use axis_engine::*;
use motion_core::{
    CmdId, CommandEvent, CommandState, Engine, ErrorId, ExecuteOutputs, Rejection, Tick,
};

pub const DT: f64 = 0.001;
pub const G: &str = "g";

pub struct P4 {
    pub e: AxisEngine,
    pub events: Vec<CommandEvent>,
    pub log: Vec<(u64, CommandEvent)>,
    pub tick: u64,
}

/// Axis config: ideal following, no lag monitoring surprises.
pub fn axis_cfg() -> AxisConfig {
    AxisConfig {
        cycle_time: DT,
        ..AxisConfig::default()
    }
}

impl P4 {
    pub fn build(axes: Vec<(String, AxisConfig)>, cfg: EngineConfig) -> Self {
        P4 {
            e: AxisEngine::with_config(axes, &cfg).unwrap_or_else(|r| panic!("config: {r}")),
            events: Vec::new(),
            log: Vec::new(),
            tick: 0,
        }
    }

    /// Axes x, y, z (defaults); group "g" = [x, y]; `tc2_mc2`.
    pub fn xy() -> Self {
        let cfg = EngineConfig {
            groups: vec![GroupConfig {
                name: G.into(),
                axes: vec!["x".into(), "y".into()],
            }],
            ..EngineConfig::default()
        };
        P4::build(
            ["x", "y", "z"]
                .iter()
                .map(|n| (n.to_string(), axis_cfg()))
                .collect(),
            cfg,
        )
    }

    /// `xy()` with all axes powered: the group is GroupStandby.
    pub fn xy_powered() -> Self {
        let mut r = P4::xy();
        for a in ["x", "y", "z"] {
            r.power(a, true).unwrap();
        }
        r.step();
        assert_eq!(r.gs().state, GroupState::Standby);
        r
    }

    pub fn power(&mut self, axis: &str, enable: bool) -> Result<AxisReply, Rejection> {
        self.e.command(AxisCommand::Power(Power {
            axis: axis.into(),
            enable,
            enable_positive: true,
            enable_negative: true,
            override_percent: 100.0,
            buffer_mode: BufferMode::Aborting,
        }))
    }

    pub fn cmd(&mut self, c: AxisCommand) -> Result<AxisReply, Rejection> {
        self.e.command(c)
    }

    pub fn g(&mut self, c: GroupCommand) -> Result<AxisReply, Rejection> {
        self.e.command(AxisCommand::Group(c))
    }

    pub fn gid(&mut self, c: GroupCommand) -> CmdId {
        self.g(c).unwrap_or_else(|r| panic!("rejected: {r}")).id
    }

    pub fn p(&mut self, c: PlatformCommand) -> Result<AxisReply, Rejection> {
        self.e.command(AxisCommand::Platform(c))
    }

    pub fn id(&mut self, c: AxisCommand) -> CmdId {
        self.cmd(c).unwrap_or_else(|r| panic!("rejected: {r}")).id
    }

    pub fn step(&mut self) {
        let t = Tick {
            index: self.tick,
            dt: DT,
        };
        self.e.step(t, &mut self.events);
        for ev in self.events.drain(..) {
            self.log.push((self.tick, ev));
        }
        self.tick += 1;
    }

    pub fn steps(&mut self, n: usize) {
        for _ in 0..n {
            self.step();
        }
    }

    /// Steps until `f` holds; returns the steps taken. Panics after `max`.
    pub fn until(&mut self, max: usize, mut f: impl FnMut(&P4) -> bool) -> usize {
        for n in 0..max {
            if f(self) {
                return n;
            }
            self.step();
        }
        panic!(
            "condition not reached within {max} steps; group {:?}",
            self.e.group(G)
        );
    }

    pub fn gs(&self) -> GroupStatus {
        self.e.group(G).unwrap()
    }

    pub fn ax(&self, a: &str) -> AxisStatus {
        self.e.status(a).unwrap()
    }

    pub fn out(&self, id: CmdId) -> ExecuteOutputs {
        self.e.outputs(id).expect("known instance")
    }

    pub fn when(&self, id: CmdId, state: CommandState) -> Option<u64> {
        self.log
            .iter()
            .find(|(_, e)| e.id == id && e.state == state)
            .map(|(t, _)| *t)
    }

    pub fn set_execute(&mut self, id: CmdId, execute: bool) {
        self.cmd(AxisCommand::SetExecute { id, execute }).unwrap();
    }
}

pub fn lin(position: Vec<f64>, velocity: f64) -> MoveLinear {
    MoveLinear {
        group: G.into(),
        position,
        velocity,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        coord_system: CoordSystem::Acs,
        buffer_mode: BufferMode::Aborting,
        transition_mode: TransitionMode::None,
    }
}

pub fn lin_abs(position: Vec<f64>, velocity: f64) -> GroupCommand {
    GroupCommand::MoveLinearAbsolute(lin(position, velocity))
}

pub fn lin_rel(distance: Vec<f64>, velocity: f64) -> GroupCommand {
    GroupCommand::MoveLinearRelative(lin(distance, velocity))
}

pub fn ghalt() -> GroupCommand {
    GroupCommand::GroupHalt(GroupHalt {
        group: G.into(),
        deceleration: 0.0,
        jerk: 0.0,
        buffer_mode: BufferMode::Aborting,
    })
}

pub fn gstop() -> GroupCommand {
    GroupCommand::GroupStop(GroupStop {
        group: G.into(),
        deceleration: 0.0,
        jerk: 0.0,
    })
}

pub fn greset() -> GroupCommand {
    GroupCommand::GroupReset { group: G.into() }
}

pub fn rel(axis: &str, distance: f64, velocity: f64) -> AxisCommand {
    AxisCommand::MoveRelative(MoveRelative {
        axis: axis.into(),
        distance,
        velocity,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        buffer_mode: BufferMode::Aborting,
        options: MoveOptions::default(),
    })
}

pub fn abs(axis: &str, position: f64, velocity: f64) -> AxisCommand {
    AxisCommand::MoveAbsolute(MoveAbsolute {
        axis: axis.into(),
        position,
        velocity,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        buffer_mode: BufferMode::Aborting,
        options: MoveOptions::default(),
    })
}

pub fn inject(axis: &str) -> AxisCommand {
    AxisCommand::Sim(Sim::InjectAxisError {
        axis: axis.into(),
        error_id: 0x4550,
    })
}

pub fn err(r: Result<AxisReply, Rejection>) -> ErrorId {
    match r {
        Err(r) => r.error_id,
        Ok(_) => panic!("expected a rejection"),
    }
}

/// The axis of the worked examples (§13): linear axis 0, µm units.
pub const A0: &str = "a0";

/// Axis 0 of §13: 1 ms, ideal following, limits far above the examples, Done without
/// settling time (so the timing of the profile is visible).
pub fn a0_cfg() -> AxisConfig {
    AxisConfig {
        cycle_time: DT,
        max_velocity: 1e6,
        acceleration: 1e6,
        deceleration: 1e6,
        jerk: 1e8,
        fast_acceleration: 5e6,
        fast_deceleration: 5e6,
        fast_jerk: 1e9,
        en_target_position_monitoring: false,
        en_position_range_monitoring: false,
        max_pos_lag_value: 1e3,
        ..AxisConfig::default()
    }
}

impl P4 {
    /// `isg_mcp` with axis 0 only, platform config `pc`; not stepped (start-up pending).
    pub fn isg_cold(pc: PlatformConfig) -> Self {
        let cfg = EngineConfig {
            platform_profile: PlatformProfile::IsgMcp,
            platform: pc,
            ..EngineConfig::default()
        };
        P4::build(vec![(A0.into(), a0_cfg())], cfg)
    }

    /// `isg_mcp`, start-up done (10 cycles), axis 0 powered: STANDSTILL.
    pub fn isg_with(pc: PlatformConfig) -> Self {
        let mut r = P4::isg_cold(pc);
        r.steps(10);
        r.power(A0, true).unwrap();
        r.step();
        assert_eq!(r.ax(A0).motion_state, MotionState::Standstill);
        r
    }

    /// `isg_mcp` with axes x, y (axis 0's config) in group "g", start-up done, both powered:
    /// the group is GroupStandby.
    pub fn isg_xy(pc: PlatformConfig) -> Self {
        let cfg = EngineConfig {
            platform_profile: PlatformProfile::IsgMcp,
            groups: vec![GroupConfig {
                name: G.into(),
                axes: vec!["x".into(), "y".into()],
            }],
            platform: pc,
        };
        let mut r = P4::build(vec![("x".into(), a0_cfg()), ("y".into(), a0_cfg())], cfg);
        r.steps(10);
        r.power("x", true).unwrap();
        r.power("y", true).unwrap();
        r.step();
        assert_eq!(r.gs().state, GroupState::Standby);
        r
    }

    /// `isg_mcp` with default platform settings, ready.
    pub fn isg() -> Self {
        P4::isg_with(PlatformConfig::default())
    }

    pub fn a0(&self) -> AxisStatus {
        self.ax(A0)
    }

    pub fn order_id(&mut self, id: CmdId) -> u32 {
        match self.p(PlatformCommand::ReadOrderId { id }).unwrap().value {
            ReplyValue::Platform(PlatformReply::OrderId(o)) => o,
            v => panic!("{v:?}"),
        }
    }

    pub fn g_order_id(&self) -> u32 {
        motion_core::Engine::snapshot(&self.e).platform.g_order_id
    }

    pub fn messages(&mut self, axis: &str) -> Vec<McMessage> {
        match self
            .p(PlatformCommand::ReadMessages { axis: axis.into() })
            .unwrap()
            .value
        {
            ReplyValue::Platform(PlatformReply::Messages(m)) => m,
            v => panic!("{v:?}"),
        }
    }

    pub fn safety(&self, axis: &str) -> AxisSafetyStatus {
        motion_core::Engine::snapshot(&self.e)
            .platform
            .axes
            .into_iter()
            .find(|a| a.name == axis)
            .unwrap()
    }
}

pub fn rel_full(axis: &str, distance: f64, v: f64, a: f64, d: f64, j: f64) -> AxisCommand {
    AxisCommand::MoveRelative(MoveRelative {
        axis: axis.into(),
        distance,
        velocity: v,
        acceleration: a,
        deceleration: d,
        jerk: j,
        buffer_mode: BufferMode::Aborting,
        options: MoveOptions::default(),
    })
}

pub fn stop(axis: &str, deceleration: f64) -> AxisCommand {
    AxisCommand::Stop(Stop {
        axis: axis.into(),
        deceleration,
        jerk: 0.0,
        options: MoveOptions::default(),
    })
}

pub fn vel(axis: &str, velocity: f64) -> AxisCommand {
    AxisCommand::MoveVelocity(MoveVelocity {
        axis: axis.into(),
        velocity,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        direction: Direction::Positive,
        buffer_mode: BufferMode::Aborting,
        options: MoveOptions::default(),
    })
}

impl P4 {
    /// One PLC cycle of the raw FB layer (§12.2) with these calls, then one MC cycle.
    pub fn cycle(&mut self, calls: &[raw::FbCall]) -> Vec<raw::FbOut> {
        let t = Tick {
            index: self.tick,
            dt: DT,
        };
        let mut ev = Vec::new();
        let o = self.e.fb_cycle(t, calls, &mut ev);
        self.tick += 1;
        o
    }
}

pub fn call(instance: &str, execute: bool, fb: AxisCommand) -> raw::FbCall {
    raw::FbCall {
        instance: instance.into(),
        execute,
        fb,
    }
}
