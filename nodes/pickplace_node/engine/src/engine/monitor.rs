//! Monitoring (pick_and_place.md §16) and the published outputs (§3.3, §18).

use super::*;

impl PickPlaceEngine {
    /// Software/hardware limits and injected faults (§16).
    pub(super) fn monitor(&mut self, events: &mut Vec<CommandEvent>) {
        if matches!(self.state, TmState::Error | TmState::Disabled) {
            return;
        }
        // Injected following error or drive fault: both report 90011 (proposal) on the axis.
        if let Some(&(axis, _kind)) = self.pending_faults.first() {
            self.pending_faults.clear();
            self.raise_error(ids::FOLLOWING_ERROR, Some(axis as usize), events);
            return;
        }
        // Following error |set − act| > following_error_limit (90011, per-axis stop).
        for q in 0..7 {
            for idx in [pose_axis_index(q), if q < 6 { q + 7 } else { 13 }] {
                let lim = self.cfg.axis(idx).following_error_limit;
                if lim > 0.0 && (self.pose[q] - self.actual[q]).abs() > lim {
                    self.raise_error(ids::FOLLOWING_ERROR, Some(idx), events);
                    return;
                }
            }
        }
        for idx in 1..=13usize {
            let a = self.cfg.axis(idx);
            if !a.sw_limit_enabled {
                continue;
            }
            let v = self.axis_value(idx);
            let vel = self.axis_velocity(idx);
            if v > a.sw_limit_pos && vel > 1e-9 {
                self.sw_active[idx - 1] = true;
                self.raise_error(ids::SW_LIMIT_POS, Some(idx), events);
                return;
            }
            if v < a.sw_limit_neg && vel < -1e-9 {
                self.sw_active[idx - 1] = true;
                self.raise_error(ids::SW_LIMIT_NEG, Some(idx), events);
                return;
            }
        }
        if self.inputs.group_enable_hw_limit {
            for i in 0..18 {
                let idx = i + 1;
                let toward_pos = idx <= 13 && self.axis_velocity(idx) > 1e-9;
                let toward_neg = idx <= 13 && self.axis_velocity(idx) < -1e-9;
                if self.inputs.hw_limit_pos[i]
                    && (!self.prev.hw_limit_pos[i]
                        || !self.prev.group_enable_hw_limit
                        || toward_pos)
                {
                    self.raise_error(ids::HW_LIMIT_POS, Some(idx), events);
                    return;
                }
                if self.inputs.hw_limit_neg[i]
                    && (!self.prev.hw_limit_neg[i]
                        || !self.prev.group_enable_hw_limit
                        || toward_neg)
                {
                    self.raise_error(ids::HW_LIMIT_NEG, Some(idx), events);
                    return;
                }
            }
        }
    }

    pub(super) fn sync_flags(&self) -> (bool, bool) {
        match (&self.motion, self.running.as_deref().map(|r| &r.phase)) {
            (Motion::Bound { .. }, _) => (true, false),
            (Motion::Running, Some(Phase::Dwell { belt, .. })) => (*belt > 0, false),
            (Motion::Running, Some(Phase::Path { run, .. })) => {
                let k = run.k();
                let accdec = k > 0.0 && k < 1.0 && (run.frame_a.is_some() || run.frame_b.is_some());
                let sync =
                    (run.frame_b.is_some() && k >= 1.0) || (run.frame_a.is_some() && k <= 0.0);
                (sync, accdec)
            }
            _ => (false, false),
        }
    }

    pub(super) fn outputs(&self) -> Outputs {
        let mut o = Outputs {
            internal_control_active: self.internal_control,
            tm_state: self.state,
            axes_enabled: self.axes_enabled(),
            axes_group_enabled: self.axes_enabled(),
            done: self.done,
            path_hold: self.path_hold,
            pulse_gripper: self.pulse_gripper,
            path_preparation_time: self.cfg.path_prep_cycles as f64 * self.last_dt,
            pre_calc_profile_time: self.precalc_time,
            profile_in_preparation: self.profile_in_preparation(),
            in_target: self.in_target,
            in_park_pos: self.at_park,
            set_target_out: self.target_out,
            ..Outputs::default()
        };
        o.error = !self.error.is_none();
        o.warning = !self.warning.is_none();
        o.error_id = if o.error {
            self.error.0
        } else {
            self.warning.0
        };
        o.busy = self.state.is_busy_state() || (self.state == TmState::Stop && !self.standstill());
        o.axes_group_homed = self.homed.iter().all(|h| *h);
        for i in 0..18 {
            o.error_info[i] = AxisErrorInfo {
                error: self.axis_errors[i] != 0,
                error_id: self.axis_errors[i],
            };
            if i < 13 {
                o.act_pos[i] = self.actual_axis_value(i + 1);
                o.act_vel[i] = (o.act_pos[i] - self.prev_actual_axis_value(i + 1)) / self.last_dt;
                o.sw_limit_enabled[i] = self.cfg.axis(i + 1).sw_limit_enabled;
            }
            if self.inputs.group_enable_hw_limit {
                o.hw_limit_switch_pos[i] = self.inputs.hw_limit_pos[i];
                o.hw_limit_switch_neg[i] = self.inputs.hw_limit_neg[i];
            }
        }
        // axSwLimitSwitchActive: the axis is at/beyond its enabled limit (or tripped it).
        for i in 0..13 {
            let a = self.cfg.axis(i + 1);
            let v = o.act_pos[i];
            o.sw_limit_switch_active_axes[i] = self.sw_active[i]
                || (a.sw_limit_enabled && (v >= a.sw_limit_pos || v <= a.sw_limit_neg));
        }
        o.sw_limit_switch_active = o.sw_limit_switch_active_axes.iter().any(|a| *a);
        o.hw_limit_switch_active =
            self.error == ids::HW_LIMIT_POS || self.error == ids::HW_LIMIT_NEG;
        o.status_agbc = StatusAgbc {
            group_enabled: o.axes_group_enabled,
            group_error: o.error,
            group_error_id: if o.error { self.error.0 } else { 0 },
            group_homed: o.axes_group_homed,
        };
        if let Some(r) = self.running.as_deref() {
            o.gripper_ctrl_active = r.gripper.enabled && r.gripper.active;
            if let Phase::Path { run, .. } = &r.phase {
                o.set_path_vel_out = run.sigma.vel;
                o.profile_point_passed = run.points_passed();
            } else {
                o.profile_point_passed = 3;
            }
        } else if self.done || self.in_target {
            o.profile_point_passed = 3;
        }
        o.signal_flow = SignalFlow {
            set_target: self.latched_set_target,
            select_axis: match &self.motion {
                Motion::Jog(j) => j.axis,
                _ => self.inputs.select_axis,
            },
            tracking_mode: self
                .running
                .as_deref()
                .map_or(self.par.tracking_mode, |r| r.job.mode),
            override_applied: self.applied_override,
            stop_inputs: [
                self.inputs.path_stop,
                self.inputs.path_halt,
                self.inputs.stop_all,
                self.inputs.path_interrupt,
            ],
        };
        let (sync, accdec) = self.sync_flags();
        o.synchronised = sync;
        o.acc_dec_sync = accdec;
        let standstill = self.vel.iter().all(|v| v.abs() < STANDSTILL_VEL);
        o.in_position = self.in_position_target.is_some()
            && standstill
            && (!self.par.pos_in_window
                || self.in_window_time * 1000.0 + 1e-9 >= self.par.time_pos_in_window);
        o
    }

    pub(super) fn make_snapshot(&self) -> PickPlaceSnapshot {
        let belts = self
            .belts
            .iter()
            .enumerate()
            .map(|(i, b)| BeltSnapshot {
                belt: (i + 1) as u8,
                configured: b.par.is_configured(),
                position: b.axis.position,
                velocity: b.axis.velocity,
                workpieces: b
                    .workpieces
                    .iter()
                    .map(|w| {
                        let pb = w.belt_position(b.axis.position);
                        let pm = b.frame().to_mcs(pb);
                        WorkpieceSnapshot {
                            id: w.id,
                            visible: visible(w.state),
                            reserved: w.reserved,
                            belt_position: [pb.x, pb.y, pb.z],
                            mcs_position: [pm.x, pm.y, pm.z],
                        }
                    })
                    .collect(),
            })
            .collect();
        let active_profile = self.running.as_deref().map(|r| {
            let (phase, sigma, length, coupling, workpiece) = match &r.phase {
                Phase::Path {
                    run,
                    leg,
                    workpiece,
                    ..
                } => (
                    if *leg == Leg::ToPark {
                        ProfilePhase::ToPark
                    } else {
                        ProfilePhase::ToTarget
                    },
                    run.sigma.pos,
                    run.geom.length,
                    run.k(),
                    *workpiece,
                ),
                Phase::WaitPark { .. } => (ProfilePhase::WaitingAtPark, 0.0, 0.0, 0.0, None),
                Phase::Dwell { workpiece, .. } => {
                    (ProfilePhase::SyncDwell, 0.0, 0.0, 1.0, *workpiece)
                }
                Phase::GripperDelay | Phase::Done => (ProfilePhase::AtTarget, 0.0, 0.0, 0.0, None),
            };
            ProfileSnapshot {
                set_target: r.job.set_target,
                phase,
                sigma,
                length,
                coupling,
                workpiece,
            }
        });
        PickPlaceSnapshot {
            cycle: self.cycle,
            time: self.time,
            state: self.state,
            tcp: self.pose,
            tcp_velocity: self.vel,
            gripper_closed: self.gripper_closed,
            held_workpiece: self.held_workpiece.map(|(_, id)| id),
            belts,
            active_profile,
            queued_profiles: self.queue.len(),
            outputs: self.outputs(),
        }
    }
}
