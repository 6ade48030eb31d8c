//! Lock-step harness for the worked examples (xplanar.md §7: cycle 1 ms, default movers).
#![allow(dead_code)]

use motion_core::{CmdId, CommandEvent, CommandState, Engine, ErrorId, Rejection, Tick};
use planar_engine::*;
use std::collections::HashMap;

/// Position tolerance of §7 [mm].
pub const POS_TOL: f64 = 0.1;
/// Angle tolerance of §7 [deg].
pub const ANG_TOL: f64 = 0.01;

pub struct Sim {
    pub eng: PlanarEngine,
    pub index: u64,
    pub dt: f64,
    /// Every state each command went through, in order.
    pub history: HashMap<CmdId, Vec<CommandState>>,
}

impl Sim {
    pub fn new(cfg: PlanarConfig) -> Sim {
        let dt = cfg.cycle_time;
        Sim {
            eng: PlanarEngine::new(cfg).expect("config"),
            index: 0,
            dt,
            history: HashMap::new(),
        }
    }

    /// Movers at the given (x, y) with defaults, plane unbounded.
    pub fn with_movers(movers: &[(&str, f64, f64)]) -> Sim {
        let cfg = PlanarConfig {
            movers: movers
                .iter()
                .map(|(n, x, y)| MoverConfig::new(n, *x, *y, 0.0))
                .collect(),
            groups: vec![GroupConfig {
                name: "G".into(),
                oid: 0,
            }],
            ..Default::default()
        };
        Sim::new(cfg)
    }

    pub fn cmd(&mut self, c: PlanarCommand) -> Result<PlanarReply, Rejection> {
        self.eng.command(c)
    }

    pub fn ok(&mut self, c: PlanarCommand) -> CmdId {
        let dbg = format!("{c:?}");
        match self.eng.command(c) {
            Ok(r) => r.id,
            Err(e) => panic!("{dbg} rejected: {e}"),
        }
    }

    pub fn err(&mut self, c: PlanarCommand) -> Rejection {
        let dbg = format!("{c:?}");
        match self.eng.command(c) {
            Ok(r) => panic!("{dbg} accepted as {:?}", r.id),
            Err(e) => e,
        }
    }

    pub fn step(&mut self) -> Vec<CommandEvent> {
        let mut ev = vec![];
        self.eng.step(
            Tick {
                index: self.index,
                dt: self.dt,
            },
            &mut ev,
        );
        self.index += 1;
        for e in &ev {
            self.history.entry(e.id).or_default().push(e.state);
        }
        ev
    }

    pub fn steps(&mut self, n: usize) {
        for _ in 0..n {
            self.step();
        }
    }

    /// Steps until `f` holds (checked after each step); panics after `timeout` s.
    pub fn run_until(&mut self, timeout: f64, mut f: impl FnMut(&PlanarSnapshot) -> bool) {
        let n = (timeout / self.dt).ceil() as usize;
        for _ in 0..n {
            self.step();
            if f(&self.eng.snapshot()) {
                return;
            }
        }
        panic!("condition not reached within {timeout} s");
    }

    pub fn state(&self, id: CmdId) -> Option<CommandState> {
        self.history.get(&id).and_then(|h| h.last().copied())
    }

    pub fn wait_final(&mut self, id: CmdId, timeout: f64) -> CommandState {
        let n = (timeout / self.dt).ceil() as usize;
        for _ in 0..n {
            if let Some(s) = self.state(id) {
                if s.is_final() {
                    return s;
                }
            }
            self.step();
        }
        panic!(
            "command {id:?} not final within {timeout} s (history {:?})",
            self.history.get(&id)
        );
    }

    pub fn snap(&self) -> PlanarSnapshot {
        self.eng.snapshot()
    }

    pub fn mover(&self, name: &str) -> MoverSnapshot {
        self.eng.snapshot().mover(name).unwrap().clone()
    }

    pub fn enable(&mut self, name: &str) {
        let id = self.ok(PlanarCommand::MoverEnable { mover: name.into() });
        assert_eq!(
            self.wait_final(id, 5.0),
            CommandState::Done,
            "enable {name}"
        );
    }

    pub fn enable_group(&mut self, name: &str) {
        let id = self.ok(PlanarCommand::GroupEnable { group: name.into() });
        assert_eq!(
            self.wait_final(id, 5.0),
            CommandState::Done,
            "enable group {name}"
        );
    }
}

pub fn mtp(mover: &str, x: f64, y: f64, c: f64) -> PlanarCommand {
    PlanarCommand::MoveToPosition {
        mover: mover.into(),
        target_position: PositionXYC::new(x, y, c),
        constraint: DynamicConstraint::default(),
        options: MoveToPositionOptions::default(),
    }
}

pub fn mtp_ref(mover: &str, x: f64, y: f64, c: f64, r: u32) -> PlanarCommand {
    PlanarCommand::MoveToPosition {
        mover: mover.into(),
        target_position: PositionXYC::with_ref(x, y, c, r),
        constraint: DynamicConstraint::default(),
        options: MoveToPositionOptions::default(),
    }
}

pub fn move_c(mover: &str, c: f64) -> PlanarCommand {
    PlanarCommand::MoveC {
        mover: mover.into(),
        target_position: c,
        constraint: DynamicConstraint::default(),
        options: MoveCOptions::default(),
    }
}

pub fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

pub fn assert_pos(m: &MoverSnapshot, x: f64, y: f64) {
    assert!(
        close(m.set_pos.x, x, POS_TOL) && close(m.set_pos.y, y, POS_TOL),
        "mover {} at ({}, {}), expected ({x}, {y})",
        m.name,
        m.set_pos.x,
        m.set_pos.y
    );
}

pub fn id_of(e: &Rejection) -> ErrorId {
    e.error_id
}

/// The two-part layout of W2/W5/W8: CS 0x01010060, Part L 0x01010020 at (0,0), Part R
/// 0x01010030 at (240,0), one tile each; processing unit configured; mover M at (120,120) on L.
pub const CS: u32 = 0x0101_0060;
pub const PART_L: u32 = 0x0101_0020;
pub const PART_R: u32 = 0x0101_0030;

pub fn two_parts() -> PlanarConfig {
    let part = |name: &str, oid: u32, x: f64| PartConfig {
        name: name.into(),
        oid,
        tiles: vec![[0.0, 0.0]],
        positions: [(1, PartPositionConfig { cs: CS, x, y: 0.0 })]
            .into_iter()
            .collect(),
        initial_index: 1,
    };
    let mut m = MoverConfig::new("M", 120.0, 120.0, 0.0);
    m.part_oid = PART_L;
    PlanarConfig {
        coordinate_systems: vec![CS],
        parts: vec![part("L", PART_L, 0.0), part("R", PART_R, 240.0)],
        environment: EnvironmentConfig {
            name: "env".into(),
            oid: 0x0101_0001,
            processing_unit_oid: 0x0101_0002,
        },
        movers: vec![m],
        ..Default::default()
    }
}

/// The jerk profile of W4: jerk +J until a ≥ A, then −J until a ≤ 0 (x only), integrated
/// exactly per cycle. Returns (p, v, a) per cycle starting after `x0`.
pub fn jerk_stream(x0: f64, j: f64, a_max: f64, dt: f64) -> Vec<(f64, f64, f64)> {
    let (mut p, mut v, mut a, mut jj) = (x0, 0.0, 0.0, j);
    let mut out = vec![];
    loop {
        p += v * dt + a * dt * dt / 2.0 + jj * dt * dt * dt / 6.0;
        v += a * dt + jj * dt * dt / 2.0;
        a += jj * dt;
        out.push((p, v, a));
        if jj > 0.0 && a >= a_max - 1e-9 {
            jj = -j;
        } else if jj < 0.0 && a <= 1e-9 {
            break;
        }
    }
    out
}

pub fn sp_x(p: f64, v: f64, a: f64, base: MoverVector) -> (MoverVector, MoverVector, MoverVector) {
    (
        MoverVector { x: p, ..base },
        MoverVector {
            x: v,
            ..Default::default()
        },
        MoverVector {
            x: a,
            ..Default::default()
        },
    )
}

/// Issue 15.3: a move off the stators ends in E_COLLISION; the mover's centre stopped on the
/// edge `x_edge` (never past it) and the mover is in Error naming the environment.
pub fn assert_stopped_at_edge(s: &mut Sim, id: CmdId, mover: &str, x_edge: f64) {
    assert_eq!(
        s.wait_final(id, 5.0),
        CommandState::Error(planar_engine::errors::E_COLLISION)
    );
    s.steps(100);
    let m = s.mover(mover);
    assert!(
        m.set_pos.x <= x_edge + 1e-6 && m.set_pos.x > x_edge - 1e-3,
        "stopped at x = {} (edge {x_edge})",
        m.set_pos.x
    );
    assert_eq!(m.state, PlanarState::Error);
    assert_eq!(m.object_info.object_type, PlanarObjectType::Environment);
    assert_eq!(m.object_info.id, s.snap().environment.oid);
}

/// Each mover's footprint (its configured size) at its set position.
pub fn footprints(
    s: &PlanarSnapshot,
    cfg: &PlanarConfig,
) -> Vec<planar_engine::geometry::ConvexPolygon> {
    s.movers
        .iter()
        .zip(&cfg.movers)
        .map(|(m, c)| {
            planar_engine::geometry::ConvexPolygon::rect(
                planar_engine::geometry::V2::new(m.set_pos.x, m.set_pos.y),
                c.width,
                c.height,
                m.set_pos.c,
            )
        })
        .collect()
}
