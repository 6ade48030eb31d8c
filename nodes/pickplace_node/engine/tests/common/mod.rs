//! Test harness: the common setup of pick_and_place.md §19 and a cycle recorder.
#![allow(dead_code)]

use motion_core::{CmdId, CommandEvent, Engine, Tick};
use pickplace_engine::{
    PickPlaceCommand, PickPlaceConfig, PickPlaceEngine, PickPlaceSnapshot, ScPar, TmState,
};

/// Cycle time of §19 [s].
pub const TS: f64 = 0.001;

/// `scPar` of the common setup: no axis limits, v 100, a = d = 1000, j 1e5, A target 180.
pub fn common_par() -> ScPar {
    let mut target_pos = ScPar::default().target_pos;
    target_pos[3] = 180.0;
    ScPar {
        max_vel: [0.0; 7],
        max_acc_dec: [0.0; 7],
        max_jerk: [0.0; 7],
        path_vel: 100.0,
        path_acc: 1000.0,
        path_dec: 1000.0,
        path_jerk: 100_000.0,
        target_pos,
        ..ScPar::default()
    }
}

/// Configuration of the common setup with TCP (0, 0, 100, 180, 0, 0, 0).
pub fn common_config() -> PickPlaceConfig {
    PickPlaceConfig {
        params: common_par(),
        initial_tcp: Some([0.0, 0.0, 100.0, 180.0, 0.0, 0.0, 0.0]),
        ..Default::default()
    }
}

/// The engine with a recorder.
pub struct Cell {
    pub eng: PickPlaceEngine,
    pub tick: u64,
    pub events: Vec<CommandEvent>,
    pub trace: Vec<PickPlaceSnapshot>,
}

impl Cell {
    /// A cell from `cfg`, not yet enabled.
    pub fn new(cfg: PickPlaceConfig) -> Cell {
        Cell {
            eng: PickPlaceEngine::new(cfg).expect("valid config"),
            tick: 0,
            events: Vec::new(),
            trace: Vec::new(),
        }
    }

    /// A cell from `cfg`, enabled and READY.
    pub fn ready(cfg: PickPlaceConfig) -> Cell {
        let mut c = Cell::new(cfg);
        c.cmd(PickPlaceCommand::SetEnable(true));
        c.cmd(PickPlaceCommand::SetRegulatorOn(true));
        c.step();
        assert_eq!(c.state(), TmState::Ready);
        c.trace.clear();
        c
    }

    pub fn cmd(&mut self, c: PickPlaceCommand) -> CmdId {
        self.eng.command(c).expect("accepted")
    }

    pub fn set_par(&mut self, f: impl FnOnce(&mut ScPar)) {
        let mut p = self.eng.params().clone();
        f(&mut p);
        self.cmd(PickPlaceCommand::SetParams(Box::new(p)));
    }

    /// A parameter write through the HMI (Internal Control).
    pub fn set_par_hmi(&mut self, f: impl FnOnce(&mut ScPar)) {
        let mut p = self.eng.params().clone();
        f(&mut p);
        self.cmd(PickPlaceCommand::Hmi(Box::new(
            PickPlaceCommand::SetParams(Box::new(p)),
        )));
    }

    pub fn step(&mut self) -> &PickPlaceSnapshot {
        self.eng.step(
            Tick {
                index: self.tick,
                dt: TS,
            },
            &mut self.events,
        );
        self.tick += 1;
        self.trace.push(self.eng.snapshot());
        self.trace.last().unwrap()
    }

    pub fn steps(&mut self, n: usize) {
        for _ in 0..n {
            self.step();
        }
    }

    /// Steps until `f` holds (returns the number of steps) or panics after `max` cycles.
    pub fn until(&mut self, max: usize, f: impl Fn(&PickPlaceSnapshot) -> bool) -> usize {
        for i in 0..max {
            if f(self.step()) {
                return i + 1;
            }
        }
        panic!(
            "condition not reached within {max} cycles; last state {:?}",
            self.trace.last().map(|s| s.state)
        );
    }

    pub fn last(&self) -> &PickPlaceSnapshot {
        self.trace.last().expect("stepped")
    }

    pub fn state(&self) -> TmState {
        self.eng.snapshot().state
    }

    /// Index into `trace` of the first cycle with a non-zero path velocity ("t = 0" of §19).
    pub fn motion_start(&self) -> usize {
        self.trace
            .iter()
            .position(|s| s.outputs.set_path_vel_out > 1e-9)
            .expect("motion started")
    }

    /// Time of trace index `i` relative to the motion start [s].
    pub fn t(&self, i: usize) -> f64 {
        (i as f64 - self.motion_start() as f64) * TS
    }

    /// Trace index nearest to time `t` after the motion start.
    pub fn at(&self, t: f64) -> &PickPlaceSnapshot {
        let i = self.motion_start() + (t / TS).round() as usize;
        &self.trace[i]
    }
}

pub fn assert_close(what: &str, got: f64, want: f64, tol: f64) {
    assert!(
        (got - want).abs() <= tol,
        "{what}: got {got}, want {want} ± {tol}"
    );
}

/// Belt 1 of W8: origin (400, 500, 100, 0, 0, 180), park (−400, 500, 300, 180, 0, 180),
/// limits 200 … 800, lrZDistBelt 50, lrSyncTimeOnBelt 0.2.
pub fn w8_belt() -> pickplace_engine::ConveyorBeltPar {
    pickplace_engine::ConveyorBeltPar {
        park_pos: [-400.0, 500.0, 300.0, 180.0, 0.0, 180.0],
        z_dist_belt: 50.0,
        conveyor_belt_origin: [400.0, 500.0, 100.0, 0.0, 0.0, 180.0],
        sync_time_on_belt: 0.2,
        lower_sync_limit: 200.0,
        upper_sync_limit: 800.0,
    }
}

/// A cell with belt 1 of W8 running at `velocity` and the TCP at `tcp`.
pub fn belt_cell(velocity: f64, tcp: [f64; 7]) -> Cell {
    belt_cell_with_axes(velocity, tcp, &[])
}

/// [`belt_cell`] with group configuration entries per axis name (`x`, `a1`, …).
pub fn belt_cell_with_axes(
    velocity: f64,
    tcp: [f64; 7],
    axes: &[(&str, pickplace_engine::AxisConfig)],
) -> Cell {
    let mut cfg = common_config();
    for (name, a) in axes {
        cfg.axes.insert(name.to_string(), *a);
    }
    cfg.initial_tcp = Some(tcp);
    cfg.belts.insert(
        "1".into(),
        pickplace_engine::BeltConfig {
            params: w8_belt(),
            initial_velocity: velocity,
            initial_position: 0.0,
        },
    );
    let mut c = Cell::ready(cfg);
    c.set_par(|p| {
        p.path_vel = 500.0;
        p.path_acc = 5000.0;
        p.path_dec = 5000.0;
        p.path_jerk = 1e6;
        p.z_start_dist = 0.0;
        p.blending_radius = 10.0;
    });
    c
}

/// Belt 2: parallel to belt 1 at Y = −500, running towards −X of MCS as well.
pub fn belt2() -> pickplace_engine::ConveyorBeltPar {
    pickplace_engine::ConveyorBeltPar {
        park_pos: [-400.0, -500.0, 300.0, 180.0, 0.0, 180.0],
        z_dist_belt: 40.0,
        conveyor_belt_origin: [400.0, -500.0, 100.0, 0.0, 0.0, 180.0],
        sync_time_on_belt: 0.1,
        lower_sync_limit: 200.0,
        upper_sync_limit: 800.0,
    }
}

/// A cell with belts 1 and 2 at velocities `v1`, `v2`, TCP at (0, 0, 200, 180, 0, 180).
pub fn two_belt_cell(v1: f64, v2: f64) -> Cell {
    let mut cfg = common_config();
    cfg.initial_tcp = Some([0.0, 0.0, 200.0, 180.0, 0.0, 180.0, 0.0]);
    cfg.belts.insert(
        "1".into(),
        pickplace_engine::BeltConfig {
            params: w8_belt(),
            initial_velocity: v1,
            initial_position: 0.0,
        },
    );
    cfg.belts.insert(
        "2".into(),
        pickplace_engine::BeltConfig {
            params: belt2(),
            initial_velocity: v2,
            initial_position: 0.0,
        },
    );
    let mut c = Cell::ready(cfg);
    c.set_par(|p| {
        p.path_vel = 500.0;
        p.path_acc = 5000.0;
        p.path_dec = 5000.0;
        p.path_jerk = 1e6;
        p.blending_radius = 10.0;
        p.z_dist_elliptical = 30.0;
    });
    c
}

/// For every rising edge of xInTarget on a belt target: the distance between the TCP and the
/// nearest workpiece of that belt (taken from the previous cycle and moved on by one cycle).
pub fn belt_hits(c: &Cell) -> Vec<(usize, u8, f64)> {
    let mut out = Vec::new();
    for i in 1..c.trace.len() {
        let (a, b) = (&c.trace[i - 1], &c.trace[i]);
        if b.outputs.in_target && !a.outputs.in_target && b.outputs.set_target_out > 0 {
            let n = b.outputs.set_target_out as usize;
            let ds = b.belts[n - 1].position - a.belts[n - 1].position;
            let d = a.belts[n - 1]
                .workpieces
                .iter()
                .map(|w| {
                    // Belts 1 and 2 run towards −X of MCS.
                    let p = [w.mcs_position[0] - ds, w.mcs_position[1], w.mcs_position[2]];
                    ((p[0] - b.tcp[0]).powi(2)
                        + (p[1] - b.tcp[1]).powi(2)
                        + (p[2] - b.tcp[2]).powi(2))
                    .sqrt()
                })
                .fold(f64::MAX, f64::min);
            out.push((i, n as u8, d));
        }
    }
    out
}
