//! MC_GearInMultiMaster (single_axis.md §4.12.4): one slave coupled to up to four masters,
//! the slave motion is the superposition of the masters' motions with one ratio each.
//!
//! Calls (Enable-type, like MC_GearInDyn): Enable↑ couples and returns the instance id; calls
//! with Enable TRUE update GearRatio1..4 / dynamics of the running instance (same id, master
//! names are latched at Enable↑); Enable↓ ends the command (Done, outputs reset): the ratios
//! are frozen and the slave **stays coupled** (§9 item 7). MC_GearOut while Enable stays TRUE
//! only decouples briefly (the coupling is kept).
//!
//! Model (spec proposals of §4.12.4), masters read with their set values (or actual values,
//! AxisCoupleSlaveToActualValues 1064) in raw coordinates, masters stepped first:
//! * without AdvancedSlaveDynamics (ASD): velocity-type, `ΔSlavePos = Σ r_eff,i·ΔMaster_i`,
//!   each `r_eff,i` slews to GearRatio_i with `|dr/dt| ≤ Acceleration / Master_i
//!   AxisMaxVelocity` (as MC_GearInDyn). Masters must be at rest at Enable↑ (0x4B05) and the
//!   slave in Standstill (or already a slave).
//! * with ASD the slave runs through a jerk-limited v/a/j limiter (slave AxisMaxVelocity,
//!   Acceleration, Deceleration, Jerk; 0 = slave default; the jerk is reduced to
//!   max(Acceleration, Deceleration)/cycle time) and may couple onto moving masters and from
//!   DiscreteMotion/ContinuousMotion (T9b):
//!   VELOSYNC tracks `v* = Σ r_i·v_i`; POSSYNC1 tracks v* until velocity-synchronous, then the
//!   ideal position `p* += Σ r_lim,i·Δm_i` (ratios slewed); POSSYNC2 tracks
//!   `p* = s0 + Σ r_i·(m_i − m_i(t0))` (current ratios, t0 = coupling instant).
//!   The phasing offset φ (§4.13) is added after the limiter.
//!
//! InGear: coupled, every r_eff at its GearRatio, and with ASD the limiter synchronous
//! (|v − v*| ≤ 1e-6, POSSYNC also |p − p*| ≤ 1e-6). Once synchronous the slave follows the
//! ideal motion exactly as long as the change of v* per cycle stays within its acceleration
//! limit (so the steady state plans nothing and allocates nothing); otherwise the limiter
//! (a Ruckig plan from the current state, every cycle) takes over again.
//! Not modelled: MC_MoveSuperImposed on a multi-master slave with ASD (the overlay shift is
//! taken back by the limiter).

use super::*;
use crate::added::*;
pub use crate::added::{GearInMultiMasterOptions, GearInMultiMasterSyncMode};
use crate::gearing::Coupling;

impl AxisSet {
    /// MC_GearInMultiMaster (§4.12.4): Enable↑ = new instance, calls with Enable TRUE = new inputs.
    pub fn gear_in_multi_master(
        &mut self,
        slave: usize,
        c: GearInMultiMaster,
    ) -> Result<FbReply, Rejection> {
        let fb = "MC_GearInMultiMaster";
        let name = self.axes[slave].name.clone();
        let ratios = [c.gear_ratio1, c.gear_ratio2, c.gear_ratio3, c.gear_ratio4];
        for (k, r) in ratios.iter().enumerate() {
            finite(&name, fb, &format!("GearRatio{}", k + 1), *r)?;
        }
        for (f, v) in [
            ("Acceleration", c.acceleration),
            ("Deceleration", c.deceleration),
            ("Jerk", c.jerk),
        ] {
            finite(&name, fb, f, v)?;
            if v < 0.0 {
                return Err(not_correct(
                    &name,
                    fb,
                    f,
                    v,
                    "must be >= 0 (0 = axis default)",
                ));
            }
        }
        let cfg = &self.axes[slave].cfg;
        let or = |x: f64, d: f64| if x > 0.0 { x } else { d };
        let (acc, dec, jerk) = (
            or(c.acceleration, cfg.acceleration),
            or(c.deceleration, cfg.deceleration),
            or(c.jerk, cfg.jerk),
        );
        let current = self.axes[slave].coupling.and_then(|cp| cp.ext.multi);
        let running = current.and_then(|m| m.owner);
        if !c.enable {
            // Enable↓: the command ends, the coupling stays with the frozen ratios.
            if let (Some(id), Some(mut cp)) = (running, self.axes[slave].coupling) {
                if let Some(mut m) = cp.ext.multi {
                    m.owner = None;
                    m.target = m.ratio;
                    cp.ext.multi = Some(m);
                }
                self.axes[slave].coupling = Some(cp);
                self.axes[slave].ext.multi_owner = None;
                self.fbs.done(id);
                self.fbs.set_execute(id, false);
                return Ok(Self::reply(id));
            }
            return Ok(self.untracked(FbValue::None));
        }
        if let (Some(id), Some(mut cp)) = (running, self.axes[slave].coupling) {
            // Cyclic update of the running instance (ratios, dynamics).
            if let Some(mut m) = cp.ext.multi {
                m.target = ratios;
                for k in 0..4 {
                    if let Some(mi) = m.masters[k] {
                        m.rate[k] = acc / self.axes[mi].cfg.max_velocity;
                    }
                }
                (m.acc, m.dec, m.jerk) = (acc, dec, jerk);
                cp.ext.multi = Some(m);
            }
            self.axes[slave].coupling = Some(cp);
            return Ok(Self::reply(id));
        }
        // A new coupling: resolve the masters ("" = unused).
        let names = [&c.master1, &c.master2, &c.master3, &c.master4];
        let mut masters = [None; 4];
        for (k, n) in names.iter().enumerate() {
            if n.is_empty() {
                continue;
            }
            let m = self.axis_index(n)?;
            if m == slave {
                return Err(reject(
                    PARAMETER_NOT_CORRECT,
                    format!("axis '{name}': {fb}: Master{} is the slave itself", k + 1),
                ));
            }
            if masters.contains(&Some(m)) {
                return Err(reject(
                    PARAMETER_NOT_CORRECT,
                    format!("axis '{name}': {fb}: master '{n}' is given twice"),
                ));
            }
            if self.follows(m, slave) {
                return Err(reject(
                    PARAMETER_NOT_CORRECT,
                    format!("axis '{name}': {fb}: coupling to '{n}' would close a loop"),
                ));
            }
            masters[k] = Some(m);
        }
        let Some(first) = masters.iter().flatten().next().copied() else {
            return Err(reject(
                PARAMETER_NOT_CORRECT,
                format!("axis '{name}': {fb}: no master given (Master1..4 all empty)"),
            ));
        };
        let asd = c.options.advanced_slave_dynamics;
        self.admit_state(slave, FbClass::GearInMultiMaster { asd }, fb)?;
        if !asd {
            for m in masters.iter().flatten() {
                let ma = &self.axes[*m];
                if ma.set.vel.abs() > 1e-9 {
                    return Err(reject(
                        COMMAND_NOT_PERMITTED,
                        format!(
                            "axis '{name}': {fb}: master '{}' is moving (v = {}); coupling onto \
                             moving masters needs Options.AdvancedSlaveDynamics",
                            ma.name, ma.set.vel
                        ),
                    ));
                }
            }
        }
        // Admitted.
        let mut inputs = [State1::default(); 4];
        let mut rate = [0.0; 4];
        for k in 0..4 {
            if let Some(m) = masters[k] {
                inputs[k] = self.master_raw(slave, m);
                rate[k] = acc / self.axes[m].cfg.max_velocity;
            }
        }
        let m0 = inputs.map(|s| s.pos);
        self.end_orphan_multi(slave);
        let id = self
            .fbs
            .admit(slave, FbKind::GearInMultiMaster, CommandState::Active);
        let a = &mut self.axes[slave];
        a.cmd_no = a.cmd_no.wrapping_add(1);
        // A previous coupling of this slave is replaced ("=" in the Syn column).
        if let Some(old) = a.coupling.take() {
            for o in [
                old.dynamic.and_then(|d| d.owner),
                old.ext.multi.and_then(|m| m.owner),
            ]
            .into_iter()
            .flatten()
            {
                self.fbs.aborted(o);
            }
        }
        a.abort_motion(&mut self.fbs);
        a.job = None;
        a.last_target = None;
        let k1 = masters.iter().position(|m| *m == Some(first)).unwrap_or(0);
        let multi = Multi {
            owner: Some(id),
            masters,
            target: ratios,
            // Without ASD a new coupling starts at GearRatio (as MC_GearInDyn).
            ratio: ratios,
            rate,
            inputs,
            m_prev: m0,
            m0,
            asd,
            sync_mode: c.options.sync_mode,
            acc,
            dec,
            jerk,
            ls: a.set,
            p_star: a.set.pos,
            pos_synced: false,
            synced: false,
            v_prev: 0.0,
        };
        a.coupling = Some(Coupling {
            master: first,
            ratio: ratios[k1],
            m0: m0[k1],
            s0: a.set.pos,
            dynamic: None,
            ext: CouplingExt {
                phase: Default::default(),
                multi: Some(multi),
            },
        });
        a.ext.multi_owner = Some(id);
        if !asd {
            if let Some(i) = self.fbs.get_mut(id) {
                i.in_velocity = true;
            }
        }
        self.recompute_order();
        Ok(Self::reply(id))
    }

    /// Ends an enabled instance whose coupling went away (GearOut with Enable FALSE is not
    /// possible while enabled; error, power off, reset, a motion command on an allowed slave,
    /// another coupling): CommandAborted, or Error with the axis error id.
    fn end_orphan_multi(&mut self, i: usize) {
        let a = &self.axes[i];
        let Some(owner) = a.ext.multi_owner else {
            return;
        };
        let live = a.coupling.and_then(|c| c.ext.multi).and_then(|m| m.owner);
        if live == Some(owner) {
            return;
        }
        let e = a.error_id;
        self.axes[i].ext.multi_owner = None;
        if e.is_none() {
            self.fbs.aborted(owner);
        } else {
            self.fbs.error(owner, e);
        }
    }

    /// True when axis `a` (indirectly) follows axis `b`.
    fn follows(&self, a: usize, b: usize) -> bool {
        let mut stack = vec![a];
        let mut seen = vec![false; self.axes.len()];
        while let Some(i) = stack.pop() {
            if i == b {
                return true;
            }
            if std::mem::replace(&mut seen[i], true) {
                continue;
            }
            if let Some(c) = self.axes[i].coupling {
                stack.extend(c.masters());
            }
        }
        false
    }

    /// The master value slave `s` couples to (set or actual, 1064), in raw coordinates.
    pub(crate) fn master_raw(&self, s: usize, m: usize) -> State1 {
        let ma = &self.axes[m];
        let ms = crate::gearing::MasterState::of(ma);
        let v = self.axes[s].master_value(&ms);
        State1 {
            pos: v.pos - ma.coord_offset,
            ..v
        }
    }

    /// Before the slave's step: this cycle's master values; ends an instance whose coupling
    /// went away (CommandAborted, or Error with the axis error id). No alloc.
    pub(crate) fn multi_master_step(&mut self, i: usize) {
        self.end_orphan_multi(i);
        let Some(mut c) = self.axes[i].coupling else {
            return;
        };
        let Some(mut m) = c.ext.multi else { return };
        for k in 0..4 {
            if let Some(mi) = m.masters[k] {
                m.inputs[k] = self.master_raw(i, mi);
            }
        }
        c.ext.multi = Some(m);
        self.axes[i].coupling = Some(c);
    }
}
