//! Test rig for collision-avoidance groups: one engine with CA axes, stepping by hand at
//! T = 1 ms, per-cycle invariants (gaps, dynamics) recorded while stepping.
#![allow(dead_code)]

use axis_engine::ca::GroupState;
use axis_engine::ca::*;
use axis_engine::ca_bench::{ca_axis_config, ca_engine_with};
use axis_engine::*;
use motion_core::{
    CmdId, CommandEvent, CommandState, Engine, ErrorId, ExecuteOutputs, Rejection, Tick,
};

pub const T: f64 = 0.001;
pub const G: &str = "g";

pub struct CaRig {
    pub e: AxisEngine,
    pub events: Vec<CommandEvent>,
    pub tick: u64,
    /// Per axis name: minimum of gap_actual − gap_target seen after `arm_gap_check`.
    pub worst_margin: f64,
    pub check_gaps: bool,
    /// Per axis: previous (v, a) to check per-cycle jerk.
    pub prev: Vec<(f64, f64)>,
    pub max_jerk_ratio: f64,
}

impl CaRig {
    pub fn new(movers: &[(&str, f64)], cfg: CaGroupConfig) -> Self {
        let m: Vec<(String, AxisConfig)> = movers
            .iter()
            .map(|(n, x)| (n.to_string(), ca_axis_config(*x)))
            .collect();
        Self::with_axes(&m, cfg)
    }

    /// Like `new`, with an own configuration per axis.
    pub fn with_axes(movers: &[(String, AxisConfig)], cfg: CaGroupConfig) -> Self {
        let e = ca_engine_with(movers, G, cfg, T).unwrap_or_else(|r| panic!("setup: {r}"));
        CaRig {
            e,
            events: Vec::new(),
            tick: 2,
            worst_margin: f64::INFINITY,
            check_gaps: false,
            prev: Vec::new(),
            max_jerk_ratio: 0.0,
        }
    }

    /// Axes powered but not grouped; group `G` configured with `cfg`, empty.
    pub fn ungrouped(movers: &[(&str, f64)], cfg: CaGroupConfig) -> Self {
        let axes = movers
            .iter()
            .map(|(n, x)| (n.to_string(), ca_axis_config(*x)))
            .collect();
        let mut e = AxisEngine::new(axes).unwrap();
        e.add_ca_group(G, cfg).unwrap();
        let mut r = CaRig {
            e,
            events: Vec::new(),
            tick: 0,
            worst_margin: f64::INFINITY,
            check_gaps: false,
            prev: Vec::new(),
            max_jerk_ratio: 0.0,
        };
        for (n, _) in movers {
            r.power(n, true);
        }
        r.step();
        r
    }

    pub fn power(&mut self, axis: &str, on: bool) {
        self.e
            .command(AxisCommand::Power(Power {
                axis: axis.into(),
                enable: on,
                enable_positive: true,
                enable_negative: true,
                override_percent: 100.0,
                buffer_mode: BufferMode::Aborting,
            }))
            .unwrap();
    }

    pub fn ca(&mut self, c: CaCommand) -> Result<AxisReply, Rejection> {
        self.e.command(AxisCommand::Ca(c))
    }

    pub fn ok(&mut self, c: CaCommand) -> CmdId {
        self.ca(c).unwrap_or_else(|r| panic!("rejected: {r}")).id
    }

    pub fn err(&mut self, c: CaCommand) -> ErrorId {
        match self.ca(c) {
            Ok(r) => panic!("accepted: {r:?}"),
            Err(r) => r.error_id,
        }
    }

    pub fn step(&mut self) {
        self.events.clear();
        self.e.step(
            Tick {
                index: self.tick,
                dt: T,
            },
            &mut self.events,
        );
        self.tick += 1;
        if self.check_gaps {
            let g = self.group();
            for a in &g.axes {
                if a.gap_actual.is_finite() {
                    self.worst_margin = self.worst_margin.min(a.gap_actual - a.gap_target);
                }
            }
        }
    }

    pub fn steps(&mut self, n: usize) {
        for _ in 0..n {
            self.step();
        }
    }

    /// Steps until `f` holds (at most `max` cycles); returns the cycles stepped.
    pub fn until(&mut self, max: usize, mut f: impl FnMut(&mut Self) -> bool) -> usize {
        for i in 0..max {
            if f(self) {
                return i;
            }
            self.step();
        }
        panic!("condition not reached within {max} cycles");
    }

    pub fn group(&self) -> CaGroupStatus {
        self.e
            .snapshot()
            .ca_groups
            .into_iter()
            .find(|g| g.name == G)
            .unwrap()
    }

    pub fn axis(&self, name: &str) -> CaAxisStatus {
        self.group()
            .axes
            .into_iter()
            .find(|a| a.name == name)
            .unwrap()
    }

    pub fn pos(&self, name: &str) -> f64 {
        self.axis(name).position
    }

    pub fn state(&self) -> GroupState {
        self.group().state
    }

    pub fn out(&self, id: CmdId) -> ExecuteOutputs {
        self.e.outputs(id).unwrap()
    }

    pub fn cmd_state(&self, id: CmdId) -> CommandState {
        let o = self.out(id);
        if o.done {
            CommandState::Done
        } else if o.error {
            CommandState::Error(o.error_id)
        } else if o.command_aborted {
            CommandState::Aborted
        } else if o.active {
            CommandState::Active
        } else {
            CommandState::Busy
        }
    }

    pub fn mv_abs(&mut self, axis: &str, pos: f64, v: f64) -> CmdId {
        self.ok(CaCommand::MoveAbsolute(MoveAbsoluteCa {
            axis: axis.into(),
            position: McLreal::Value(pos),
            velocity: McLreal::Value(v),
            ..Default::default()
        }))
    }

    pub fn mv_rel(&mut self, axis: &str, d: f64, v: f64) -> CmdId {
        self.ok(CaCommand::MoveRelative(MoveRelativeCa {
            axis: axis.into(),
            distance: McLreal::Value(d),
            velocity: McLreal::Value(v),
            ..Default::default()
        }))
    }

    pub fn enable(&mut self) -> CmdId {
        self.ok(CaCommand::GroupEnable { group: G.into() })
    }
    pub fn disable(&mut self) -> CmdId {
        self.ok(CaCommand::GroupDisable { group: G.into() })
    }
    pub fn reset(&mut self) -> CmdId {
        self.ok(CaCommand::GroupReset { group: G.into() })
    }
    pub fn add(&mut self, axis: &str, ident: u32) -> Result<AxisReply, Rejection> {
        self.ca(CaCommand::AddAxisToGroup {
            group: G.into(),
            axis: axis.into(),
            ident_in_group: udint_to_identingroup(ident),
        })
    }
    pub fn remove(&mut self, ident: u32) -> Result<AxisReply, Rejection> {
        self.ca(CaCommand::RemoveAxisFromGroup {
            group: G.into(),
            ident_in_group: udint_to_identingroup(ident),
        })
    }
}

/// Open or ring group config of §10 (default gap 100, Standard, Positive).
pub fn ring(len: f64) -> CaGroupConfig {
    CaGroupConfig {
        rail_length: len,
        rail_is_ring: true,
        ..CaGroupConfig::default()
    }
}

pub fn open(len: f64) -> CaGroupConfig {
    CaGroupConfig {
        rail_length: len,
        rail_is_ring: false,
        ..CaGroupConfig::default()
    }
}

/// MC_MoveVelocity of the master "MA" (positive, deceleration = acceleration, jerk 1e5).
pub fn master_velocity(velocity: f64, acceleration: f64) -> AxisCommand {
    AxisCommand::MoveVelocity(MoveVelocity {
        axis: "MA".into(),
        velocity,
        acceleration,
        deceleration: acceleration,
        jerk: 100000.0,
        direction: Direction::Positive,
        buffer_mode: BufferMode::Aborting,
        options: Default::default(),
    })
}

/// The §10.9 setting: master "MA" outside the group cruising at 500 mm/s and at 0, slave "S"
/// (at `slave`) the only axis of a group with `cfg`.
pub fn gear_rig(cfg: CaGroupConfig, slave: f64) -> CaRig {
    let mut r = CaRig::ungrouped(&[("MA", -300.0), ("S", slave)], cfg);
    r.add("S", 1).unwrap();
    r.enable();
    r.e.command(master_velocity(500.0, 10000.0)).unwrap();
    r.until(5000, |r| r.e.status("MA").unwrap().set_pos >= 0.0);
    r
}
