//! External setpoint generator (single_axis.md §4.6): MC_ExtSetPointGenEnable,
//! MC_ExtSetPointGenDisable, MC_ExtSetPointGenFeed, MC_ExtSetPointGenFeedWithTorque.
//!
//! Model (spec proposals): while enabled, SetPos/SetVelo/SetAcc are the last fed values
//! (`PlcToNc.ExtSetPos/Velo/Acc`) every cycle; before the first feed the axis holds its set
//! position. The state is ContinuousMotion while the fed velocity is ≠ 0, else Standstill
//! (§2.2 note); StateDWord bit 14 `ExtSetPointGenEnabled` is set. `Position` of the enable is
//! only the target for the position monitoring (InTargetPosition when reached; RELATIVE =
//! relative to the set position at the edge). Disable keeps the last fed position; a fed
//! velocity ≠ 0 is stopped by the internal generator with AxisDec/AxisJerk.
//!
//! Admission: Enable only in Standstill (else 0x4B01, §2.4); Disable in every state.
//! Motion commands on an enabled axis are rejected with 0x4B01 unless
//! AxisAllowMotionCmdToExtSetAxis (1066) = TRUE; then the generator is disabled and the
//! command takes over. MC_Stop, MC_Reset and MC_Power are always possible (MC_Stop disables
//! the generator). An axis error or power off disables the generator.
//! The feed functions (FUNCTION : BOOL, return value always FALSE) only copy their inputs,
//! whether the generator is enabled or not; bad input (non-finite, Direction ∉ {−1, 0, 1} →
//! 0x7F03) is refused. TorqueOffset is forwarded (`PlcToNc.ExtTorque`, [`crate::added_inputs::ExtStatus`])
//! only when the generator was enabled with `Options.UseTorqueOffset`.

use super::*;
use crate::added::*;

impl AxisSet {
    /// MC_ExtSetPointGenEnable (§4.6.1).
    pub fn ext_set_point_gen_enable(
        &mut self,
        ax: usize,
        c: ExtSetPointGenEnable,
    ) -> Result<FbReply, Rejection> {
        let fb = "MC_ExtSetPointGenEnable";
        finite(&c.axis, fb, "Position", c.position)?;
        self.admit_state(ax, FbClass::ExtSetPointGenEnable, fb)?;
        let id = self
            .fbs
            .admit(ax, FbKind::ExtSetPointGenEnable, CommandState::Busy);
        let a = &mut self.axes[ax];
        a.cmd_no = a.cmd_no.wrapping_add(1);
        let target = match c.position_type {
            PositionType::Absolute => c.position,
            PositionType::Relative => a.set.pos + c.position,
        };
        a.ext.ext_gen = ExtGen {
            enabled: true,
            use_torque_offset: c.options.use_torque_offset,
            fed: State1::at_rest(a.set.pos),
            direction: 0,
            fed_since_enable: false,
            torque_offset: 0.0,
        };
        a.target_pos = target;
        a.in_target = false;
        a.in_target_timer = 0.0;
        a.last_target = None;
        self.instant_done.push(id);
        Ok(Self::reply(id))
    }

    /// MC_ExtSetPointGenDisable (§4.6.2).
    pub fn ext_set_point_gen_disable(&mut self, ax: usize) -> Result<FbReply, Rejection> {
        let fb = "MC_ExtSetPointGenDisable";
        self.admit_state(ax, FbClass::ExtSetPointGenDisable, fb)?;
        let id = self
            .fbs
            .admit(ax, FbKind::ExtSetPointGenDisable, CommandState::Busy);
        let a = &mut self.axes[ax];
        a.cmd_no = a.cmd_no.wrapping_add(1);
        a.disable_ext_gen();
        self.instant_done.push(id);
        Ok(Self::reply(id))
    }

    /// MC_ExtSetPointGenFeed / MC_ExtSetPointGenFeedWithTorque (§4.6); `fb` names the FB in messages.
    pub fn ext_set_point_gen_feed(
        &mut self,
        ax: usize,
        fb: &str,
        s: State1,
        direction: i32,
        torque_offset: f64,
    ) -> Result<FbReply, Rejection> {
        let a = &mut self.axes[ax];
        for (f, v) in [
            ("Position", s.pos),
            ("Velocity", s.vel),
            ("Acceleration", s.acc),
            ("TorqueOffset", torque_offset),
        ] {
            finite(&a.name, fb, f, v)?;
        }
        if !(-1..=1).contains(&direction) {
            return Err(reject(
                ErrorId::ENUM_OUT_OF_RANGE,
                format!(
                    "axis '{}': {fb}: Direction = {direction} must be -1, 0 or 1",
                    a.name
                ),
            ));
        }
        let g = &mut a.ext.ext_gen;
        g.fed = s;
        g.direction = direction;
        g.fed_since_enable = true;
        if g.use_torque_offset && g.enabled {
            g.torque_offset = torque_offset;
        }
        Ok(self.untracked(FbValue::Bool(false)))
    }

    /// Motion commands on an axis fed by the external generator (§2.4 note): 0x4B01 unless
    /// AxisAllowMotionCmdToExtSetAxis (1066).
    pub(crate) fn ext_setpoint_admission(
        &self,
        ax: usize,
        fb: FbClass,
        fb_name: &str,
    ) -> Result<(), Rejection> {
        let a = &self.axes[ax];
        let motion = matches!(
            fb,
            FbClass::Halt
                | FbClass::MoveDiscrete
                | FbClass::MoveContinuous
                | FbClass::TorqueControl
                | FbClass::Jog
                | FbClass::HomeDefault
                | FbClass::HomeNoMotion
                | FbClass::GearIn
                | FbClass::GearInDyn
                | FbClass::GearInMultiMaster { .. }
                | FbClass::ExtSetPointGenEnable
        );
        if motion && a.ext.ext_gen.enabled && !a.cfg.allow_motion_cmd_to_ext_set_axis {
            return Err(reject(
                AXIS_CANNOT_BE_STARTED,
                format!(
                    "axis '{}': {fb_name} not allowed while the external setpoint generator \
                     is enabled (AxisAllowMotionCmdToExtSetAxis = FALSE)",
                    a.name
                ),
            ));
        }
        Ok(())
    }

    /// Before the axis' step: the fed values become the set values. No alloc.
    pub(crate) fn ext_setpoint_step(&mut self, i: usize) {
        let a = &mut self.axes[i];
        if !a.ext.ext_gen.enabled {
            return;
        }
        if !a.error_id.is_none() || !a.controller_on {
            a.ext.ext_gen.enabled = false;
            return;
        }
        if a.job.is_some() || a.torque.is_some() || a.coupling.is_some() || a.homing.is_some() {
            // A command took over (MC_Stop, or a motion command allowed by 1066).
            a.ext.ext_gen.enabled = false;
            return;
        }
        if a.ext.ext_gen.fed_since_enable {
            a.set = a.ext.ext_gen.fed;
        }
    }
}
