//! Test rig: one engine, stepping by hand, helpers to build FB calls.
#![allow(dead_code)]

use axis_engine::*;
use motion_core::{
    CmdId, CommandEvent, CommandState, Engine, ErrorId, ExecuteOutputs, Rejection, Tick,
};

pub const AX: &str = "x";
pub const DT: f64 = 0.002;

pub struct Rig {
    pub e: AxisEngine,
    pub events: Vec<CommandEvent>,
    pub log: Vec<(u64, CommandEvent)>,
    pub tick: u64,
}

impl Rig {
    pub fn with(cfg: AxisConfig) -> Self {
        Rig {
            e: AxisEngine::new(vec![(AX.to_string(), cfg)]).unwrap(),
            events: Vec::new(),
            log: Vec::new(),
            tick: 0,
        }
    }

    /// Default axis, not powered.
    pub fn new() -> Self {
        Rig::with(AxisConfig::default())
    }

    /// Power on (Enable and both feed enables TRUE) and one cycle: Standstill.
    pub fn powered_with(cfg: AxisConfig) -> Self {
        let mut r = Rig::with(cfg);
        r.power(true);
        r.step();
        assert_eq!(r.st().motion_state, MotionState::Standstill);
        r
    }

    pub fn powered() -> Self {
        Rig::powered_with(AxisConfig::default())
    }

    pub fn power(&mut self, enable: bool) {
        self.power_full(enable, true, true, 100.0, BufferMode::Aborting)
            .unwrap();
    }

    pub fn power_full(
        &mut self,
        enable: bool,
        pos: bool,
        neg: bool,
        ovr: f64,
        bm: BufferMode,
    ) -> Result<AxisReply, Rejection> {
        self.cmd(AxisCommand::Power(Power {
            axis: AX.into(),
            enable,
            enable_positive: pos,
            enable_negative: neg,
            override_percent: ovr,
            buffer_mode: bm,
        }))
    }

    pub fn cmd(&mut self, c: AxisCommand) -> Result<AxisReply, Rejection> {
        self.e.command(c)
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

    /// Steps until `f` holds; returns the number of steps taken. Panics after `max`.
    pub fn until(&mut self, max: usize, mut f: impl FnMut(&Rig) -> bool) -> usize {
        for n in 0..max {
            if f(self) {
                return n;
            }
            self.step();
        }
        panic!(
            "condition not reached within {max} steps; status {:?}",
            self.st()
        );
    }

    pub fn st(&self) -> AxisStatus {
        self.e.status(AX).unwrap()
    }

    pub fn out(&self, id: CmdId) -> ExecuteOutputs {
        self.e.outputs(id).expect("known instance")
    }

    pub fn state_of(&self, id: CmdId) -> Option<CommandState> {
        self.log
            .iter()
            .rev()
            .find(|(_, e)| e.id == id)
            .map(|(_, e)| e.state)
    }

    /// Cycle index at which `id` first reported `state`.
    pub fn when(&self, id: CmdId, state: CommandState) -> Option<u64> {
        self.log
            .iter()
            .find(|(_, e)| e.id == id && e.state == state)
            .map(|(t, _)| *t)
    }

    pub fn set_pos(&mut self, p: f64) {
        let id = self.id(set_position(p));
        self.step();
        assert!(self.out(id).done);
    }
}

pub fn move_abs(position: f64, velocity: f64) -> MoveAbsolute {
    MoveAbsolute {
        axis: AX.into(),
        position,
        velocity,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        buffer_mode: BufferMode::Aborting,
        options: MoveOptions::default(),
    }
}

pub fn abs(position: f64, velocity: f64) -> AxisCommand {
    AxisCommand::MoveAbsolute(move_abs(position, velocity))
}

pub fn abs_bm(position: f64, velocity: f64, bm: BufferMode) -> AxisCommand {
    AxisCommand::MoveAbsolute(MoveAbsolute {
        buffer_mode: bm,
        ..move_abs(position, velocity)
    })
}

pub fn abs_dyn(
    position: f64,
    velocity: f64,
    a: f64,
    d: f64,
    j: f64,
    bm: BufferMode,
) -> AxisCommand {
    AxisCommand::MoveAbsolute(MoveAbsolute {
        acceleration: a,
        deceleration: d,
        jerk: j,
        buffer_mode: bm,
        ..move_abs(position, velocity)
    })
}

/// MC_MoveRelative with its dynamics and BufferMode.
pub fn rel_dyn(distance: f64, v: f64, a: f64, d: f64, j: f64, bm: BufferMode) -> AxisCommand {
    AxisCommand::MoveRelative(MoveRelative {
        axis: AX.into(),
        distance,
        velocity: v,
        acceleration: a,
        deceleration: d,
        jerk: j,
        buffer_mode: bm,
        options: MoveOptions::default(),
    })
}

/// MC_MoveAdditive with its dynamics and BufferMode.
pub fn add_dyn(distance: f64, v: f64, a: f64, d: f64, j: f64, bm: BufferMode) -> AxisCommand {
    AxisCommand::MoveAdditive(MoveAdditive {
        axis: AX.into(),
        distance,
        velocity: v,
        acceleration: a,
        deceleration: d,
        jerk: j,
        buffer_mode: bm,
        options: MoveOptions::default(),
    })
}

/// MC_MoveVelocity with its dynamics, direction and BufferMode.
pub fn vel_dyn(v: f64, dir: Direction, a: f64, d: f64, j: f64, bm: BufferMode) -> AxisCommand {
    AxisCommand::MoveVelocity(MoveVelocity {
        acceleration: a,
        deceleration: d,
        jerk: j,
        buffer_mode: bm,
        ..move_vel(v, dir)
    })
}

pub fn rel(distance: f64, velocity: f64) -> AxisCommand {
    AxisCommand::MoveRelative(MoveRelative {
        axis: AX.into(),
        distance,
        velocity,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        buffer_mode: BufferMode::Aborting,
        options: MoveOptions::default(),
    })
}

pub fn add(distance: f64, velocity: f64) -> AxisCommand {
    AxisCommand::MoveAdditive(MoveAdditive {
        axis: AX.into(),
        distance,
        velocity,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        buffer_mode: BufferMode::Aborting,
        options: MoveOptions::default(),
    })
}

pub fn move_vel(velocity: f64, direction: Direction) -> MoveVelocity {
    MoveVelocity {
        axis: AX.into(),
        velocity,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        direction,
        buffer_mode: BufferMode::Aborting,
        options: MoveOptions::default(),
    }
}

pub fn vel(velocity: f64) -> AxisCommand {
    AxisCommand::MoveVelocity(move_vel(velocity, Direction::Positive))
}

pub fn modulo(position: f64, direction: Direction) -> AxisCommand {
    AxisCommand::MoveModulo(MoveModulo {
        axis: AX.into(),
        position,
        velocity: 100.0,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        direction,
        buffer_mode: BufferMode::Aborting,
        options: MoveOptions::default(),
    })
}

pub fn halt(dec: f64, jerk: f64, bm: BufferMode) -> AxisCommand {
    AxisCommand::Halt(Halt {
        axis: AX.into(),
        deceleration: dec,
        jerk,
        buffer_mode: bm,
        options: MoveOptions::default(),
    })
}

pub fn stop(dec: f64, jerk: f64) -> AxisCommand {
    AxisCommand::Stop(Stop {
        axis: AX.into(),
        deceleration: dec,
        jerk,
        options: MoveOptions::default(),
    })
}

pub fn reset() -> AxisCommand {
    AxisCommand::Reset(Reset { axis: AX.into() })
}

pub fn set_position(p: f64) -> AxisCommand {
    AxisCommand::SetPosition(SetPosition {
        axis: AX.into(),
        position: p,
        mode: false,
        options: SetPositionOptions::default(),
    })
}

pub fn execute(id: CmdId, level: bool) -> AxisCommand {
    AxisCommand::SetExecute { id, execute: level }
}

pub fn inject(e: u32) -> AxisCommand {
    AxisCommand::Sim(Sim::InjectAxisError {
        axis: AX.into(),
        error_id: e,
    })
}

pub fn err(id: u32) -> ErrorId {
    ErrorId(id)
}

/// Asserts the exclusivity rules of §3.2 (with the MC_Stop exception when `stop`).
pub fn assert_exclusive(o: &ExecuteOutputs, stop: bool) {
    let n = [o.busy, o.done, o.error, o.command_aborted]
        .iter()
        .filter(|b| **b)
        .count();
    if !stop {
        assert!(n <= 1, "Busy/Done/Error/CommandAborted exclusive: {o:?}");
    }
    let m = [o.active, o.done, o.error, o.command_aborted]
        .iter()
        .filter(|b| **b)
        .count();
    if !stop {
        assert!(m <= 1, "Active/Done/Error/CommandAborted exclusive: {o:?}");
    }
    assert!(!o.active || o.busy, "Active implies Busy: {o:?}");
    assert!(!(o.error && o.done), "Done never with Error: {o:?}");
    assert_eq!(o.error, o.error_id.0 != 0, "ErrorID only with Error: {o:?}");
}
