//! Motion of one cycle: path profiles and their phases (§7, §15), stops (§9), jogging (§5),
//! homing (§6), gripper pulses (§10), endless tracking modes (§11).

use super::*;

impl PickPlaceEngine {
    /// Starts individual stops of the 7 pose axes; `dj` = (dec, jerk) for all axes, or the
    /// per-axis `alrStopDec`/`alrStopJerk` when `None`.
    pub(super) fn start_axis_stop(&mut self, dj: Option<(f64, f64)>) {
        let mut profiles = [Profile1::hold(State1::at_rest(0.0)); 7];
        for q in 0..7 {
            let i = pose_axis_index(q) - 1;
            let (d, j) = dj.unwrap_or((self.par.stop_dec[i], self.par.stop_jerk[i]));
            let start = State1 {
                pos: self.pose[q],
                vel: self.vel[q],
                acc: self.acc[q],
            };
            let lim = Limits {
                velocity: self.vel[q].abs().max(1.0) * 2.0,
                acceleration: d,
                deceleration: d,
                jerk: j,
            };
            profiles[q] = Profile1::stopping(start, &lim)
                .or_else(|_| Profile1::stopping(State1 { acc: 0.0, ..start }, &lim))
                .unwrap_or_else(|_| Profile1::hold(State1::at_rest(self.pose[q])));
        }
        self.motion = Motion::AxisStop { profiles, t: 0.0 };
    }

    pub(super) fn stop_params(&self, halt: bool) -> (f64, f64) {
        let (d_path, j_path) = match self.running.as_deref() {
            Some(Running {
                phase: Phase::Path { run, .. },
                ..
            }) => {
                let l = run.limits[run.sub];
                (
                    l.deceleration * self.applied_override,
                    l.jerk * self.applied_override,
                )
            }
            _ => (self.par.path_dec, self.par.path_jerk),
        };
        if halt {
            (self.par.path_halt_dec.max(d_path), self.par.path_jerk)
        } else {
            (
                self.par.path_stop_dec.max(d_path),
                self.par.path_stop_jerk.max(j_path),
            )
        }
    }

    /// Brakes the current motion for a stop input (T5) or an interrupt (T19).
    pub(super) fn brake(&mut self, stop_all: bool, halt: bool) {
        self.done = false;
        if let Some(r) = self.running.as_deref_mut() {
            r.gripper.active = false;
        }
        if stop_all {
            // §9.3: per-axis stop; the path reference is lost, the resume re-plans.
            let (sync, accdec) = self.sync_flags();
            if sync || accdec {
                self.stop_all_sync = true;
            }
            if let Some(r) = self.running.as_deref_mut() {
                r.replan = true;
            }
            self.start_axis_stop(None);
            return;
        }
        let (d, j) = self.stop_params(halt);
        match &mut self.motion {
            Motion::Running => {
                let Some(r) = self.running.as_deref_mut() else {
                    return;
                };
                match &mut r.phase {
                    Phase::Path { run, .. } if !run.coupled() => run.stop(d, j),
                    Phase::Path { .. } | Phase::Dwell { .. } => {
                        // Coupled to a belt: ramp the superposition out in MCS (§9.2 proposal).
                        r.replan = true;
                        self.start_axis_stop(Some((d, j)));
                    }
                    Phase::WaitPark { .. } | Phase::GripperDelay | Phase::Done => {}
                }
            }
            Motion::Bound { .. } => self.start_axis_stop(Some((d, j))),
            Motion::Jog(_) | Motion::Homing(_) | Motion::Service(_) => self.start_axis_stop(None),
            Motion::Still | Motion::AxisStop { .. } => {}
        }
    }

    pub(super) fn standstill(&self) -> bool {
        match &self.motion {
            Motion::Still => true,
            Motion::Bound { frame, .. } => {
                self.belts[frame.belt - 1].axis.velocity.abs() < STANDSTILL_VEL
            }
            Motion::AxisStop { profiles, t } => profiles.iter().all(|p| *t >= p.duration()),
            Motion::Running => match self.running.as_deref().map(|r| &r.phase) {
                Some(Phase::Path { run, .. }) => run.at_rest(),
                Some(Phase::Dwell { belt, .. }) => {
                    self.belts[belt - 1].axis.velocity.abs() < STANDSTILL_VEL
                }
                _ => true,
            },
            Motion::Jog(j) => j.stopping && j.t >= j.profile.duration(),
            Motion::Homing(_) | Motion::Service(_) => false,
        }
    }

    pub(super) fn jog_allowed_toward(&self, axis: u8, positive: bool) -> bool {
        let i = axis as usize - 1;
        let sw = self.cfg.axis(axis as usize);
        if sw.sw_limit_enabled {
            let v = self.axis_value(axis as usize);
            if positive && v >= sw.sw_limit_pos || !positive && v <= sw.sw_limit_neg {
                return false;
            }
        }
        if self.inputs.group_enable_hw_limit
            && (positive && self.inputs.hw_limit_pos[i] || !positive && self.inputs.hw_limit_neg[i])
        {
            return false;
        }
        true
    }

    pub(super) fn start_jog(&mut self, positive: bool, return_to_stop: bool) -> bool {
        let axis = self.inputs.select_axis;
        if axis == 0 || axis > 13 || !self.jog_allowed_toward(axis, positive) {
            return false;
        }
        let jp = match axis {
            1..=3 => self.par.cartesian_jog,
            4..=6 => self.par.orientation_jog,
            _ => self.par.real_axis_jog,
        };
        let lim = Limits {
            velocity: jp.vel,
            acceleration: jp.acc,
            deceleration: jp.dec,
            jerk: jp.jerk,
        };
        let start = State1::at_rest(self.axis_value(axis as usize));
        let Ok(profile) =
            Profile1::to_velocity(start, if positive { jp.vel } else { -jp.vel }, &lim)
        else {
            return false;
        };
        self.motion = Motion::Jog(JogRun {
            axis,
            positive,
            profile,
            t: 0.0,
            stopping: false,
            return_to_stop,
            limits: lim,
        });
        self.done = false;
        self.in_target = false;
        self.in_position_target = None;
        self.at_park = false;
        self.set_state(if positive {
            TmState::JogPos
        } else {
            TmState::JogNeg
        });
        true
    }

    pub(super) fn start_homing(&mut self, id: Option<CmdId>, events: &mut Vec<CommandEvent>) {
        self.done = false;
        let h = HomingRun {
            id,
            stage: 0,
            axes: Vec::new(),
            timer: 0.0,
            search: Vec::new(),
        };
        self.motion = Motion::Homing(Box::new(h));
        self.in_target = false;
        self.in_position_target = None;
        self.emit(events, id, CommandState::Active);
        self.set_state(TmState::Homing);
    }

    /// Pulse of the gripper (§10).
    pub(super) fn gripper_pulse(&mut self, kind: GripperEvent) {
        self.pulse_gripper = true;
        if self.running.as_deref().is_some_and(|r| r.job.mode > 0) {
            self.gripper_closed = kind == GripperEvent::Close;
            // A close pulse within grip_capture_distance of a workpiece attaches it (§10).
            self.held_workpiece = None;
            if kind == GripperEvent::Close {
                let tcp = v3(&self.actual);
                let mut best = self.cfg.grip_capture_distance;
                for (i, b) in self.belts.iter().enumerate() {
                    for w in b
                        .workpieces
                        .iter()
                        .filter(|w| w.state == WorkpieceState::Visible)
                    {
                        let d = (b.workpiece_mcs(w) - tcp).norm();
                        if d <= best {
                            best = d;
                            self.held_workpiece = Some((i + 1, w.id));
                        }
                    }
                }
            }
        }
        let e = CellEvent::GripperPulse {
            cycle: self.cycle,
            kind,
        };
        self.push_event(e);
    }

    /// Advances the running profile in MOVE_PP (phases, gripper, queue).
    pub(super) fn advance_running(&mut self, dt: f64, e: &Edges, events: &mut Vec<CommandEvent>) {
        let Some(mut r) = self.running.take() else {
            return;
        };
        let mut finished_job = false;
        let mut pulse: Option<GripperEvent> = None;
        match &mut r.phase {
            Phase::Path {
                run,
                leg,
                belt,
                workpiece,
            } => {
                if self.advance_path(run, dt) {
                    // Slowed for an AXIS_REF maximum (§7.8 (2)): the planned lead time no longer
                    // holds, so the pulse comes at the profile end (as for the override, §10).
                    r.gripper.active = false;
                }
                if run.sigma.pos > 0.0 {
                    // xInParkPos / xInTarget hold until the TCP actually leaves.
                    self.at_park = false;
                    self.in_target = false;
                    self.target_out = r.job.set_target;
                }
                if *leg == Leg::Main
                    && r.gripper.enabled
                    && r.gripper.active
                    && !r.gripper.pulsed
                    && r.gripper.lead > 0.0
                    && run.is_nominal()
                    && run.remaining_time() <= r.gripper.lead + 1e-9
                {
                    r.gripper.pulsed = true;
                    pulse = Some(r.gripper.kind);
                }
                if run.drive == Drive::Finished {
                    let end_pose = run.pose(&|b| self.belts[b - 1].axis.position);
                    self.pose = end_pose;
                    match (*leg, *belt) {
                        (Leg::ToPark, Some(n)) if r.job.target == Target::ParkOnly(n) => {
                            self.at_park = true;
                            r.phase = Phase::Done;
                            finished_job = true;
                        }
                        (Leg::ToPark, Some(n)) => {
                            self.at_park = true;
                            r.phase = Phase::WaitPark {
                                belt: n,
                                prep_left: None,
                            };
                        }
                        (_, Some(n)) => {
                            // Belt target reached: end of lowering, start of the synchronous dwell.
                            // A belt leg always has its target frame; MCS (Δ = 0) otherwise.
                            let frame = run.frame_b.unwrap_or(MovingFrame {
                                belt: n,
                                dir: Vec3::zeros(),
                                s_ref: 0.0,
                                c: Vec3::zeros(),
                            });
                            let mut base = run.end_pose;
                            let g = run.geom.position(run.geom.length);
                            base[0] = g.x;
                            base[1] = g.y;
                            base[2] = g.z;
                            let wp = *workpiece;
                            if let Some(id) = wp {
                                let kind = if r.job.role == Role::Place {
                                    WorkpieceEventKind::Placed
                                } else {
                                    WorkpieceEventKind::Picked
                                };
                                let ev = CellEvent::Workpiece {
                                    cycle: self.cycle,
                                    belt: n as u8,
                                    id,
                                    kind,
                                };
                                self.push_event(ev);
                            }
                            self.in_target = true;
                            r.phase = Phase::Dwell {
                                remaining: self.belts[n - 1].par.sync_time_on_belt,
                                frame,
                                base,
                                belt: n,
                                workpiece: wp,
                            };
                            self.end_of_profile_gripper(&mut r.gripper, &mut pulse);
                        }
                        (_, None) => {
                            self.in_target = true;
                            self.in_position_target = Some(end_pose);
                            self.end_of_profile_gripper(&mut r.gripper, &mut pulse);
                            if r.gripper.after.is_some() {
                                // A negative lead is served before the next profile starts.
                                r.phase = Phase::GripperDelay;
                            } else {
                                r.phase = Phase::Done;
                                finished_job = true;
                            }
                        }
                    }
                }
            }
            Phase::WaitPark { .. } if self.abort_requested && r.job.mode > 0 => {
                // xAbort in an endless mode while waiting at the park position: nothing of the
                // leg is left to finish (§11).
                finished_job = true;
            }
            Phase::WaitPark { belt, prep_left } => {
                let n = *belt;
                if prep_left.is_none() {
                    self.delete_missed_on(n);
                    let b = &self.belts[n - 1];
                    let eligible = b
                        .workpieces
                        .iter()
                        .find(|w| w.state == WorkpieceState::Visible && !w.reserved)
                        .is_some_and(|w| b.belt_x(w) >= b.par.lower_sync_limit);
                    if eligible {
                        *prep_left = Some(self.cfg.path_prep_cycles);
                    }
                }
                // Preparation counts the cycle of the eligibility (§8, W9: ≤ 25 cycles).
                if let Some(k) = prep_left {
                    *k = k.saturating_sub(1);
                    if *k == 0 {
                        let job = r.job.clone();
                        match self.plan_belt_leg(&job, n, None, true) {
                            Ok(Some((run, wp))) => {
                                self.precalc_time = run.precalc_time();
                                r.phase = Phase::Path {
                                    run: Box::new(run),
                                    leg: Leg::Main,
                                    belt: Some(n),
                                    workpiece: Some(wp),
                                };
                            }
                            Ok(None) => {
                                r.phase = Phase::WaitPark {
                                    belt: n,
                                    prep_left: None,
                                }
                            }
                            Err(err) => {
                                self.running = Some(r);
                                self.raise_error(err, None, events);
                                return;
                            }
                        }
                    }
                }
            }
            Phase::Dwell { remaining, .. } => {
                *remaining -= dt;
                if let Some(a) = &mut r.gripper.after {
                    *a -= dt;
                    if *a <= 1e-9 {
                        r.gripper.after = None;
                        pulse = Some(r.gripper.kind);
                    }
                }
                if e.ack_gripper || *remaining <= 1e-9 {
                    if r.gripper.after.take().is_some() {
                        pulse = Some(r.gripper.kind);
                    }
                    finished_job = true;
                }
            }
            Phase::GripperDelay => {
                let a = r.gripper.after.map_or(0.0, |a| a - dt);
                if a <= 1e-9 {
                    r.gripper.after = None;
                    pulse = Some(r.gripper.kind);
                    finished_job = true;
                } else {
                    r.gripper.after = Some(a);
                }
            }
            Phase::Done => finished_job = true,
        }
        if let Some(k) = pulse {
            self.running = Some(r);
            self.gripper_pulse(k);
            r = self.running.take().expect("just stored");
        }
        if finished_job {
            self.finish_job(*r, events);
        } else {
            self.running = Some(r);
        }
    }

    pub(super) fn end_of_profile_gripper(&self, g: &mut Gripper, pulse: &mut Option<GripperEvent>) {
        if !g.enabled || g.pulsed {
            return;
        }
        g.pulsed = true;
        if g.active && g.lead < 0.0 {
            g.after = Some(-g.lead);
        } else {
            *pulse = Some(g.kind);
        }
    }

    /// A job ended: bind to the belt (after a dwell), start the next one or go to READY (T18).
    pub(super) fn finish_job(&mut self, r: Running, events: &mut Vec<CommandEvent>) {
        let pose_now = self.pose;
        if let Phase::Dwell {
            belt,
            workpiece: Some(id),
            ..
        } = r.phase
        {
            // The PCS is released when the workpiece was picked/placed (§11).
            self.belts[belt - 1].workpieces.retain(|w| w.id != id);
        }
        match &r.phase {
            Phase::Dwell {
                frame, base, belt, ..
            } if *belt > 0 => {
                let b = &self.belts[*belt - 1];
                // Belt X of the reached workpiece: from the frame's base point back to belt coordinates.
                let f = b.frame();
                let p_b =
                    f.rotation.inverse() * (v3(base) + frame.delta(b.axis.position) - f.origin);
                self.motion = Motion::Bound {
                    frame: *frame,
                    base: *base,
                    wp_x0: p_b.x,
                    wp_s0: b.axis.position,
                };
                self.refresh_bound_pose();
            }
            _ => {
                self.motion = Motion::Still;
                self.pose = pose_now;
            }
        }
        // Endless modes (§11): the command's id is carried from leg to leg; it completes when
        // the loop ends (xAbort: Done, as xDone) or is replaced by a new mode (Aborted, §18).
        let mut next: Option<Job> = None;
        let mut carried = false;
        match self.next_mode.take() {
            Some((m, new_id)) if m != r.job.mode => {
                if r.job.mode > 0 {
                    self.emit(events, r.job.id, CommandState::Aborted);
                } else {
                    self.emit(events, r.job.id, CommandState::Done);
                }
                if m > 0 {
                    let mut j = self.make_job(0, new_id);
                    j.mode = m;
                    next = Some(j);
                }
            }
            _ if r.job.mode > 0 && !self.abort_requested => {
                let mut j = self.next_leg(&r.job);
                j.id = r.job.id;
                next = Some(j);
                carried = true;
            }
            _ => self.emit(events, r.job.id, CommandState::Done),
        }
        if next.is_none() {
            next = self.queue.pop_front();
        }
        if let Some(job) = next {
            let id = job.id;
            match self.start_job(job) {
                Ok(mut nr) => {
                    nr.active_emitted = carried;
                    self.running = Some(Box::new(nr));
                    self.motion = Motion::Running;
                    self.mark_active(events);
                }
                Err(err) => {
                    self.emit(events, id, CommandState::Error(err));
                    self.raise_error(err, None, events);
                }
            }
            return;
        }
        if self.append_prep.is_some() {
            // The next profile is still being prepared: wait for it (pose held).
            return;
        }
        self.abort_requested = false;
        self.done = true;
        self.set_state(TmState::Ready);
    }

    /// Advances the motion of this cycle and writes the new set-point pose.
    pub(super) fn advance_motion(&mut self, dt: f64, e: &Edges, events: &mut Vec<CommandEvent>) {
        // Override (§12): clamp to 0 … 1 with a warning.
        let mut ov = self.inputs.override_;
        if !(0.0..=1.0).contains(&ov) {
            ov = ov.clamp(0.0, 1.0);
            if self.prev.override_ != self.inputs.override_ {
                self.set_warning(ids::OVERRIDE_OUT_OF_RANGE);
            }
        }
        if ov != self.applied_override {
            self.applied_override = ov;
            if let Some(r) = self.running.as_deref_mut() {
                r.gripper.active = false;
                if let Phase::Path { run, .. } = &mut r.phase {
                    run.set_override(ov);
                }
            }
        }
        if let Some((left, _)) = &mut self.append_prep {
            if *left > 1 {
                *left -= 1;
            } else if let Some((_, job)) = self.append_prep.take() {
                self.queue.push_back(job);
                if self.running.is_none() && self.state == TmState::MovePp {
                    let job = self.queue.pop_front().expect("just pushed");
                    let id = job.id;
                    match self.start_job(job) {
                        Ok(r) => {
                            self.running = Some(Box::new(r));
                            self.motion = Motion::Running;
                            self.mark_active(events);
                        }
                        Err(err) => {
                            self.emit(events, id, CommandState::Error(err));
                            self.raise_error(err, None, events);
                        }
                    }
                }
            }
        }
        let mut belt_s = [0.0; MAX_BELTS];
        for (s, b) in belt_s.iter_mut().zip(&self.belts) {
            *s = b.axis.position;
        }
        let s_of = |b: usize| belt_s[b - 1];
        match &mut self.motion {
            Motion::Still => {}
            Motion::Bound { frame, base, .. } => {
                let p = v3(base) + frame.delta(s_of(frame.belt));
                self.pose = *base;
                self.pose[0] = p.x;
                self.pose[1] = p.y;
                self.pose[2] = p.z;
            }
            Motion::AxisStop { profiles, t } => {
                *t += dt;
                for q in 0..7 {
                    self.pose[q] = profiles[q].at(*t).pos;
                }
            }
            Motion::Jog(j) => {
                j.t += dt;
                let v = j.profile.at(j.t).pos;
                let axis = j.axis as usize;
                self.set_axis_value(axis, v);
            }
            Motion::Service(s) => {
                s.t += dt;
                let v = s.profile.at(s.t).pos;
                let axis = s.axis as usize;
                self.set_axis_value(axis, v);
            }
            Motion::Homing(_) => self.advance_homing(dt, events),
            Motion::Running => {
                if self.state == TmState::MovePp && !std::mem::take(&mut self.start_next_cycle) {
                    self.advance_running(dt, e, events);
                } else if let Some(mut r) = self.running.take() {
                    // STOP / PATH_INTERRUPT / held: only braking on the path.
                    if let Phase::Path { run, .. } = &mut r.phase {
                        if run.drive != Drive::Run {
                            self.advance_path(run, dt);
                        }
                    }
                    self.running = Some(r);
                }
                if let Some(r) = self.running.as_deref() {
                    match &r.phase {
                        Phase::Path { run, .. } => self.pose = run.pose(&s_of),
                        Phase::Dwell {
                            frame, base, belt, ..
                        } if *belt > 0 => {
                            let p = v3(base) + frame.delta(s_of(frame.belt));
                            self.pose = *base;
                            self.pose[0] = p.x;
                            self.pose[1] = p.y;
                            self.pose[2] = p.z;
                        }
                        _ => {}
                    }
                }
            }
        }
        // §7.8 (2): the set-points of path and belt motion keep the AXIS_REF maxima.
        if !matches!(self.motion, Motion::Running | Motion::Bound { .. }) {
            self.prev_nominal = self.pose;
        } else if self.clamp_to_axis_max(dt, events) {
            if let Some(r) = self.running.as_deref_mut() {
                r.gripper.active = false;
            }
        }
        if matches!(self.motion, Motion::Running)
            && matches!(self.state, TmState::Stop | TmState::PathInterrupt)
        {
            if let Some(r) = self.running.as_deref_mut() {
                r.hold_pose = self.pose;
            }
        }
    }

    pub(super) fn advance_homing(&mut self, dt: f64, events: &mut Vec<CommandEvent>) {
        let Motion::Homing(mut h) = std::mem::replace(&mut self.motion, Motion::Still) else {
            return;
        };
        // Start the next non-empty stage (§6).
        while h.axes.is_empty() {
            h.stage += 1;
            if h.stage > 12 {
                self.emit(events, h.id, CommandState::Done);
                self.done = true;
                self.set_state(TmState::Ready);
                return;
            }
            h.axes = (0..7)
                .filter(|&i| self.par.homing_order[i] == h.stage)
                .collect();
            h.timer = 0.0;
            h.search = h
                .axes
                .iter()
                .map(|&i| {
                    let hp = if self.par.use_home_ext_parameter {
                        self.par.home_ext_parameter[i]
                    } else {
                        Default::default()
                    };
                    if hp.mode == 1 {
                        let lim = Limits {
                            velocity: hp.vel,
                            acceleration: hp.acc,
                            deceleration: hp.acc,
                            jerk: f64::INFINITY,
                        };
                        let start = self.axis_value(7 + i);
                        let v = if hp.positive_direction {
                            hp.vel
                        } else {
                            -hp.vel
                        };
                        Profile1::to_velocity(State1::at_rest(start), v, &lim)
                            .ok()
                            .map(|profile| AxisSearch {
                                profile,
                                t: 0.0,
                                start,
                                found: false,
                            })
                    } else {
                        None
                    }
                })
                .collect();
        }
        h.timer += dt;
        let mut stage_done = true;
        for k in 0..h.axes.len() {
            let i = h.axes[k];
            let axis = 7 + i;
            match &mut h.search[k] {
                None => {
                    if h.timer + 1e-12 >= self.cfg.homing_stage_time {
                        self.set_axis_value(axis, self.par.home_position[i]);
                        self.homed[i] = true;
                    } else {
                        stage_done = false;
                    }
                }
                Some(s) => {
                    s.t += dt;
                    let st = s.profile.at(s.t);
                    self.set_axis_value(axis, st.pos);
                    if !s.found {
                        stage_done = false;
                        let hp = self.par.home_ext_parameter[i];
                        if self.inputs.home_abs_switch[i] && !self.prev.home_abs_switch[i] {
                            // The switch point becomes the home position; then stop.
                            let shift = self.par.home_position[i] - st.pos;
                            let lim = Limits {
                                velocity: hp.vel,
                                acceleration: hp.acc,
                                deceleration: hp.acc,
                                jerk: f64::INFINITY,
                            };
                            let moved = State1 {
                                pos: self.par.home_position[i],
                                ..st
                            };
                            s.profile = Profile1::stopping(moved, &lim)
                                .unwrap_or_else(|_| Profile1::hold(State1::at_rest(moved.pos)));
                            s.t = 0.0;
                            s.found = true;
                            s.start += shift;
                            self.set_axis_value(axis, self.par.home_position[i]);
                        } else if hp.max_search_dist > 0.0
                            && (st.pos - s.start).abs() > hp.max_search_dist
                        {
                            self.motion = Motion::Still;
                            self.raise_error(ids::HOMING_FAILED, Some(axis), events);
                            return;
                        }
                    } else if s.t < s.profile.duration() {
                        stage_done = false;
                    } else {
                        self.homed[i] = true;
                    }
                }
            }
        }
        if stage_done {
            h.axes.clear();
        }
        self.motion = Motion::Homing(h);
    }
}
