//! Test rig for several named axes (phasing, multi-master gearing): all powered, stepped by
//! hand, with the FB calls the tests need.
#![allow(dead_code)]

use axis_engine::*;
use motion_core::{CmdId, Engine, ErrorId, ExecuteOutputs, Rejection, Tick};

pub const DT: f64 = 0.002;

pub struct Axes {
    pub e: AxisEngine,
    pub tick: u64,
    pub ev: Vec<motion_core::CommandEvent>,
}

impl Axes {
    /// Axes with default configuration (the last one may get `last_cfg`), powered, one cycle.
    pub fn new(names: &[&str], last_cfg: AxisConfig) -> Self {
        let n = names.len();
        let e = AxisEngine::new(
            names
                .iter()
                .enumerate()
                .map(|(i, s)| {
                    let cfg = if i + 1 == n {
                        last_cfg.clone()
                    } else {
                        AxisConfig::default()
                    };
                    (s.to_string(), cfg)
                })
                .collect(),
        )
        .unwrap();
        let mut t = Axes {
            e,
            tick: 0,
            ev: vec![],
        };
        for s in names {
            t.cmd(AxisCommand::Power(Power {
                axis: s.to_string(),
                enable: true,
                enable_positive: true,
                enable_negative: true,
                override_percent: 100.0,
                buffer_mode: BufferMode::Aborting,
            }))
            .unwrap();
        }
        t.step();
        t
    }
    pub fn cmd(&mut self, c: AxisCommand) -> Result<AxisReply, Rejection> {
        self.e.command(c)
    }
    pub fn id(&mut self, c: AxisCommand) -> CmdId {
        self.cmd(c).unwrap_or_else(|r| panic!("rejected: {r}")).id
    }
    pub fn step(&mut self) {
        self.e.step(
            Tick {
                index: self.tick,
                dt: DT,
            },
            &mut self.ev,
        );
        self.ev.clear();
        self.tick += 1;
    }
    pub fn steps(&mut self, n: usize) {
        for _ in 0..n {
            self.step();
        }
    }
    pub fn until(&mut self, max: usize, f: impl Fn(&Axes) -> bool) -> usize {
        for n in 0..max {
            if f(self) {
                return n;
            }
            self.step();
        }
        panic!("condition not reached within {max} cycles");
    }
    pub fn st(&self, n: &str) -> AxisStatus {
        self.e.status(n).unwrap()
    }
    pub fn ext(&self, n: &str) -> ExtStatus {
        self.e.ext_status(n).unwrap()
    }
    pub fn out(&self, id: CmdId) -> ExecuteOutputs {
        self.e.outputs(id).unwrap()
    }
    pub fn fb(&self, id: CmdId) -> FbOutputs {
        self.e.fb_outputs(id).unwrap()
    }
    pub fn extra(&mut self, id: CmdId) -> Option<ExtraOutputs> {
        match self.cmd(AxisCommand::ReadFbOutputs { id }).unwrap().value {
            ReplyValue::Outputs(o) => o.extra,
            v => panic!("unexpected {v:?}"),
        }
    }
    pub fn gear_in(
        &mut self,
        master: &str,
        slave: &str,
        ratio: f64,
    ) -> Result<AxisReply, Rejection> {
        self.cmd(AxisCommand::GearIn(GearIn {
            master: master.into(),
            slave: slave.into(),
            ratio_numerator: ratio,
            ratio_denominator: 1,
            acceleration: 0.0,
            deceleration: 0.0,
            jerk: 0.0,
            buffer_mode: BufferMode::Aborting,
        }))
    }
    pub fn vel(&mut self, axis: &str, v: f64) -> CmdId {
        self.id(AxisCommand::MoveVelocity(MoveVelocity {
            axis: axis.into(),
            velocity: v,
            acceleration: 0.0,
            deceleration: 0.0,
            jerk: 0.0,
            direction: Direction::Positive,
            buffer_mode: BufferMode::Aborting,
            options: MoveOptions::default(),
        }))
    }
    pub fn mv(&mut self, axis: &str, position: f64, v: f64) -> CmdId {
        self.id(AxisCommand::MoveAbsolute(MoveAbsolute {
            axis: axis.into(),
            position,
            velocity: v,
            acceleration: 0.0,
            deceleration: 0.0,
            jerk: 0.0,
            buffer_mode: BufferMode::Aborting,
            options: MoveOptions::default(),
        }))
    }
    pub fn gear_out(&mut self, slave: &str) -> CmdId {
        self.id(AxisCommand::GearOut(GearOut {
            slave: slave.into(),
        }))
    }
    /// Asserts a rejection with `id` that leaves every axis as it was.
    pub fn rejects(&mut self, c: AxisCommand, id: u32) {
        let names: Vec<String> = self.e.axis_names().map(String::from).collect();
        let before: Vec<AxisStatus> = names.iter().map(|n| self.st(n)).collect();
        let e = self
            .cmd(c.clone())
            .expect_err(&format!("{c:?} must be rejected"));
        assert_eq!(e.error_id, ErrorId(id), "{c:?}: {}", e.message);
        let after: Vec<AxisStatus> = names.iter().map(|n| self.st(n)).collect();
        assert_eq!(before, after, "{c:?}: axes unchanged");
    }
}

pub fn phasing_abs(master: &str, slave: &str, shift: f64, v: f64) -> PhasingAbsolute {
    PhasingAbsolute {
        master: master.into(),
        slave: slave.into(),
        continuous_update: false,
        phase_shift: shift,
        velocity: v,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        buffer_mode: BufferMode::Aborting,
    }
}

pub fn phasing_rel(master: &str, slave: &str, shift: f64, v: f64) -> PhasingRelative {
    PhasingRelative {
        master: master.into(),
        slave: slave.into(),
        continuous_update: false,
        phase_shift: shift,
        velocity: v,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        buffer_mode: BufferMode::Aborting,
    }
}

pub fn halt_phasing(master: &str, slave: &str) -> HaltPhasing {
    HaltPhasing {
        master: master.into(),
        slave: slave.into(),
        deceleration: 0.0,
        jerk: 0.0,
        buffer_mode: BufferMode::Aborting,
    }
}

pub fn multi(slave: &str, masters: [&str; 4], ratios: [f64; 4], asd: bool) -> GearInMultiMaster {
    GearInMultiMaster {
        slave: slave.into(),
        master1: masters[0].into(),
        master2: masters[1].into(),
        master3: masters[2].into(),
        master4: masters[3].into(),
        enable: true,
        gear_ratio1: ratios[0],
        gear_ratio2: ratios[1],
        gear_ratio3: ratios[2],
        gear_ratio4: ratios[3],
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        buffer_mode: BufferMode::Aborting,
        options: GearInMultiMasterOptions {
            advanced_slave_dynamics: asd,
            sync_mode: GearInMultiMasterSyncMode::VeloSync,
        },
    }
}
