//! The state machine of pick_and_place.md §4.2 (T1 … T24), pulses and edges (§18), path
//! preparation and appending (§8), resume (§9.2, §9.4).

use super::*;

impl PickPlaceEngine {
    pub(super) fn apply_pulses(&mut self) {
        // A pulse input is TRUE for one cycle, then FALSE for at least one cycle.
        self.inputs.reset_error = false;
        self.inputs.execute = false;
        self.inputs.abort = false;
        self.inputs.ack_gripper = false;
        self.inputs.group_home_execute = false;
        self.current_pulse_ids = [None; 5];
        let mut fired = [false; 5];
        let mut rest = VecDeque::new();
        while let Some(p) = self.pulses.pop_front() {
            let k = p.kind as usize;
            let was = match p.kind {
                PulseKind::ResetError => self.prev.reset_error,
                PulseKind::Execute => self.prev.execute,
                PulseKind::Abort => self.prev.abort,
                PulseKind::AckGripper => self.prev.ack_gripper,
                PulseKind::GroupHome => self.prev.group_home_execute,
            };
            if fired[k] || was {
                rest.push_back(p);
                continue;
            }
            fired[k] = true;
            self.current_pulse_ids[k] = p.id;
            match p.kind {
                PulseKind::ResetError => self.inputs.reset_error = true,
                PulseKind::Execute => {
                    self.inputs.execute = true;
                    self.inputs.set_target = p.set_target;
                }
                PulseKind::Abort => self.inputs.abort = true,
                PulseKind::AckGripper => self.inputs.ack_gripper = true,
                PulseKind::GroupHome => self.inputs.group_home_execute = true,
            }
        }
        self.pulses = rest;
    }

    pub(super) fn sim_detection(&mut self) {
        for i in 0..MAX_BELTS {
            if let Some((d, left)) = self.sim_detect_active[i] {
                let b = &mut self.belts[i];
                if b.receive && left == 0 {
                    b.valid_pos = true;
                    b.initial_object_position = d.position;
                    self.sim_detect_active[i] = Some((d, u32::MAX));
                } else if left == u32::MAX || (!b.receive && left == 0) {
                    b.receive = false;
                    b.valid_pos = false;
                    self.sim_detect_active[i] = None;
                } else {
                    b.receive = false;
                    self.sim_detect_active[i] = Some((d, left - 1));
                    if left - 1 == 0 {
                        b.valid_pos = true;
                        b.initial_object_position = d.position;
                        self.sim_detect_active[i] = Some((d, u32::MAX));
                    }
                }
                continue;
            }
            if let Some(d) = self.sim_detect[i].pop_front() {
                let b = &mut self.belts[i];
                b.receive = true;
                b.initial_object_position = d.position;
                if d.delay == 0 {
                    b.valid_pos = true;
                    self.sim_detect_active[i] = Some((d, u32::MAX));
                } else {
                    self.sim_detect_active[i] = Some((d, d.delay));
                }
            }
        }
    }

    pub(super) fn edges(&self) -> Edges {
        let (i, p) = (&self.inputs, &self.prev);
        Edges {
            reset: i.reset_error && !p.reset_error,
            home: i.group_home_execute && !p.group_home_execute,
            jog_pos: i.jog_pos && !p.jog_pos,
            jog_neg: i.jog_neg && !p.jog_neg,
            execute: i.execute && !p.execute,
            abort: i.abort && !p.abort,
            ack_gripper: i.ack_gripper && !p.ack_gripper,
        }
    }

    pub(super) fn axes_enabled(&self) -> bool {
        self.inputs.enable && self.inputs.regulator_on_all
    }

    /// `xProfileInPreparation` (§8): a profile is being prepared or the queue is full.
    pub fn profile_in_preparation(&self) -> bool {
        let running = usize::from(self.running.is_some());
        self.prep.is_some()
            || self.append_prep.is_some()
            || running + self.queue.len() >= self.cfg.profile_queue_capacity
    }

    /// Warning for an edge command that is ignored (§4.2).
    pub(super) fn ignored_edge(&mut self, events: &mut Vec<CommandEvent>, id: Option<CmdId>) {
        let w = if self.axes_enabled() {
            ids::COMMAND_NOT_ALLOWED
        } else {
            ids::AXES_NOT_ENABLED
        };
        self.set_warning(w);
        self.emit(events, id, CommandState::Error(w));
    }

    /// State machine of §4.2 for this cycle (evaluation order T1, T3, T5, T19/T20, rest).
    pub(super) fn transitions(&mut self, e: &Edges, events: &mut Vec<CommandEvent>) {
        let before = self.state;
        self.transitions_inner(e, events);
        // Edge commands that no transition of the state consumed: warning 90010 / 90009 (§4.2).
        let home_id = self.current_pulse_ids[PulseKind::GroupHome as usize];
        let handled_home = matches!(before, TmState::Ready | TmState::Error | TmState::Disabled)
            || !self.inputs.enable;
        if e.home && !handled_home {
            self.ignored_edge(events, home_id);
        }
        let jog_edge = (e.jog_pos || e.jog_neg) && self.inputs.select_axis != 0;
        let handled_jog = matches!(
            before,
            TmState::Ready | TmState::Stop | TmState::Disabled | TmState::JogPos | TmState::JogNeg
        ) || !self.inputs.enable;
        if jog_edge && !handled_jog {
            self.ignored_edge(events, None);
        }
        let handled_abort = matches!(
            before,
            TmState::Ready
                | TmState::Stop
                | TmState::PathInterrupt
                | TmState::MovePp
                | TmState::Error
                | TmState::Disabled
        ) || !self.inputs.enable;
        if e.abort && !handled_abort {
            self.ignored_edge(events, None);
        }
    }

    pub(super) fn transitions_inner(&mut self, e: &Edges, events: &mut Vec<CommandEvent>) {
        let exec_id = self.current_pulse_ids[PulseKind::Execute as usize];
        let home_id = self.current_pulse_ids[PulseKind::GroupHome as usize];
        // T1
        if !self.inputs.enable {
            if self.state != TmState::Disabled {
                self.discard_all(events, CommandState::Aborted);
                if !self.standstill() {
                    self.start_axis_stop(None);
                }
                self.done = false;
                self.set_state(TmState::Disabled);
            }
            if e.execute {
                self.ignored_edge(events, exec_id);
            }
            if e.home {
                self.ignored_edge(events, home_id);
            }
            return;
        }
        if self.state == TmState::Disabled {
            // T2
            self.set_state(if self.error.is_none() {
                TmState::Ready
            } else {
                TmState::Error
            });
        }
        if e.reset && self.state != TmState::Error {
            self.warning = ErrorId::NONE;
        }
        // Axes switched off while moving: drives stop at once (ideal sim); motion is discarded.
        if !self.axes_enabled()
            && matches!(
                self.state,
                TmState::MovePp
                    | TmState::PathInterrupt
                    | TmState::PreparingPath
                    | TmState::JogPos
                    | TmState::JogNeg
                    | TmState::Homing
                    | TmState::Service
            )
        {
            self.discard_all(events, CommandState::Aborted);
            self.motion = Motion::Still;
            self.set_state(TmState::Ready);
        }
        if let Some(id) = self.cancel_request.take() {
            self.apply_cancel(id, events);
        }
        let stop_any = self.inputs.stop_all || self.inputs.path_stop || self.inputs.path_halt;
        match self.state {
            TmState::Disabled => {}
            TmState::Error => {
                // T4
                if e.reset && self.standstill() && self.error_cause_gone() {
                    self.error = ErrorId::NONE;
                    self.warning = ErrorId::NONE;
                    self.axis_errors = [0; 18];
                    self.sw_active = [false; 18];
                    self.motion = Motion::Still;
                    self.set_state(TmState::Ready);
                }
                if e.execute {
                    self.emit(events, exec_id, CommandState::Error(self.error));
                }
                if e.home {
                    self.emit(events, home_id, CommandState::Error(self.error));
                }
            }
            s if stop_any && s != TmState::Stop && !self.service_jog_keeps_running() => {
                // T5
                if s == TmState::PreparingPath {
                    if let Some((_, Prep::New(j))) = self.prep.take() {
                        self.emit(events, j.id, CommandState::Aborted);
                    }
                    self.prep = None;
                }
                if let Some((_, j)) = self.append_prep.take() {
                    self.queue.push_back(j);
                }
                if let Motion::Homing(h) = &self.motion {
                    let hid = h.id;
                    self.emit(events, hid, CommandState::Aborted);
                }
                self.brake(
                    self.inputs.stop_all,
                    !self.inputs.path_stop && self.inputs.path_halt,
                );
                self.path_hold = self.running.is_some();
                self.set_state(TmState::Stop);
                if e.execute {
                    self.ignored_edge(events, exec_id);
                }
            }
            TmState::Stop => {
                if self.inputs.stop_all
                    && !self.prev.stop_all
                    && !matches!(self.motion, Motion::AxisStop { .. })
                {
                    self.brake(true, false);
                }
                let at_rest = self.standstill();
                if at_rest && !matches!(self.motion, Motion::Running | Motion::Jog(_)) {
                    self.motion = Motion::Still;
                }
                if at_rest && self.stop_all_sync {
                    self.stop_all_sync = false;
                    self.raise_error(ids::STOP_ALL_DURING_SYNC, None, events);
                    return;
                }
                if at_rest && std::mem::take(&mut self.cancel_stop) {
                    // Cancel: the halted path is aborted at standstill (§18).
                    self.discard_all(events, CommandState::Aborted);
                }
                if e.abort && at_rest && self.path_hold {
                    // T22
                    self.discard_all(events, CommandState::Aborted);
                } else if (e.jog_pos || e.jog_neg)
                    && at_rest
                    && !self.inputs.stop_all
                    && self.axes_enabled()
                {
                    // T23
                    let positive = e.jog_pos && !self.inputs.jog_neg;
                    if !self.start_jog(positive, true) {
                        self.set_warning(ids::COMMAND_NOT_ALLOWED);
                    }
                } else if !stop_any && at_rest {
                    // T6
                    self.set_state(TmState::Ready);
                } else if e.execute {
                    self.ignored_edge(events, exec_id);
                }
            }
            TmState::Ready => self.ready(e, events, exec_id, home_id),
            TmState::PreparingPath => {
                if e.execute {
                    self.set_warning(ids::PROFILE_BUFFER_FULL);
                    self.emit(
                        events,
                        exec_id,
                        CommandState::Error(ids::PROFILE_BUFFER_FULL),
                    );
                }
                self.preparing(events);
            }
            TmState::MovePp => {
                if self.inputs.path_interrupt {
                    // T19
                    self.brake(false, false);
                    self.path_hold = true;
                    self.set_state(TmState::PathInterrupt);
                    return;
                }
                if e.execute {
                    self.append(events, exec_id);
                }
                if e.abort {
                    if self.running.as_ref().is_some_and(|r| r.job.mode > 0) {
                        self.abort_requested = true;
                    } else {
                        self.ignored_edge(events, None);
                    }
                }
            }
            TmState::PathInterrupt => {
                let at_rest = self.standstill();
                if !self.inputs.path_interrupt {
                    // T20
                    if at_rest && !matches!(self.motion, Motion::Running) {
                        self.motion = Motion::Still;
                    }
                    self.resume(events);
                } else if e.abort && at_rest {
                    // T21
                    self.discard_all(events, CommandState::Aborted);
                    self.motion = Motion::Still;
                    self.set_state(TmState::Ready);
                } else if e.execute {
                    self.ignored_edge(events, exec_id);
                }
            }
            TmState::JogPos | TmState::JogNeg => {
                if let Motion::Jog(j) = &mut self.motion {
                    let held = if j.positive {
                        self.inputs.jog_pos
                    } else {
                        self.inputs.jog_neg
                    };
                    if !held && !j.stopping {
                        let st = j.profile.at(j.t);
                        if let Ok(p) = Profile1::stopping(st, &j.limits) {
                            j.profile = p;
                            j.t = 0.0;
                        }
                        j.stopping = true;
                    }
                    // T9
                    if j.stopping
                        && j.t >= j.profile.duration()
                        && !self.inputs.jog_pos
                        && !self.inputs.jog_neg
                    {
                        let back = j.return_to_stop && stop_any;
                        self.motion = Motion::Still;
                        self.set_state(if back { TmState::Stop } else { TmState::Ready });
                    }
                }
                if e.execute {
                    self.ignored_edge(events, exec_id);
                }
            }
            TmState::Homing => {
                if e.execute {
                    self.ignored_edge(events, exec_id);
                }
            }
            TmState::Service => {
                if !self.inputs.service.move_abs && self.standstill_service() {
                    self.motion = Motion::Still;
                    self.set_state(TmState::Ready);
                }
                if e.execute {
                    self.ignored_edge(events, exec_id);
                }
            }
        }
    }

    /// One cycle of path preparation (the edge cycle counts): T16 / T17 after
    /// `path_prep_cycles` cycles (§8).
    pub(super) fn preparing(&mut self, events: &mut Vec<CommandEvent>) {
        if let Some((left, _)) = &mut self.prep {
            *left = left.saturating_sub(1);
            if *left > 0 {
                return;
            }
        }
        let Some((_, prep)) = self.prep.take() else {
            self.set_state(TmState::Ready);
            return;
        };
        match prep {
            Prep::New(job) => {
                let id = job.id;
                match self.start_job(*job) {
                    Ok(r) => {
                        self.running = Some(Box::new(r));
                        self.motion = Motion::Running;
                        self.path_hold = false;
                        self.start_next_cycle = true;
                        self.set_state(TmState::MovePp);
                        self.mark_active(events);
                    }
                    Err(err) => {
                        self.emit(events, id, CommandState::Error(err));
                        self.raise_error(err, None, events);
                    }
                }
            }
            Prep::Resume => self.resume(events),
        }
    }

    /// `Engine::cancel` of the running profile: a path halt, the abort follows at standstill.
    fn apply_cancel(&mut self, id: CmdId, events: &mut Vec<CommandEvent>) {
        match self.state {
            TmState::PreparingPath => {
                if matches!(&self.prep, Some((_, Prep::New(j))) if j.id == Some(id)) {
                    self.prep = None;
                    self.emit(events, Some(id), CommandState::Aborted);
                    self.set_state(TmState::Ready);
                }
            }
            TmState::MovePp | TmState::PathInterrupt => {
                if let Some((_, j)) = self.append_prep.take() {
                    self.queue.push_back(j);
                }
                self.brake(false, true);
                self.path_hold = true;
                self.cancel_stop = true;
                self.set_state(TmState::Stop);
            }
            TmState::Stop => self.cancel_stop = true,
            TmState::Ready if self.path_hold => {
                self.discard_all(events, CommandState::Aborted);
                if matches!(self.motion, Motion::Running) {
                    self.motion = Motion::Still;
                }
            }
            _ => {}
        }
    }

    /// T23 jogs while the stop input that held the path is still TRUE; only a new `xStopALL`
    /// edge stops them.
    pub(super) fn service_jog_keeps_running(&self) -> bool {
        let new_stop_all = self.inputs.stop_all && !self.prev.stop_all;
        matches!(&self.motion, Motion::Jog(j) if j.return_to_stop) && !new_stop_all
    }

    pub(super) fn standstill_service(&self) -> bool {
        match &self.motion {
            Motion::Service(s) => s.t >= s.profile.duration(),
            _ => true,
        }
    }

    pub(super) fn error_cause_gone(&self) -> bool {
        // HW limit: reset allowed while active; only motion away from the switch is then
        // permitted (§16 proposal), enforced by jog admission and the monitor.
        true
    }

    pub(super) fn ready(
        &mut self,
        e: &Edges,
        events: &mut Vec<CommandEvent>,
        exec_id: Option<CmdId>,
        home_id: Option<CmdId>,
    ) {
        if e.execute {
            if !self.axes_enabled() {
                self.ignored_edge(events, exec_id);
            } else if self.profile_in_preparation() && !self.path_hold {
                self.set_warning(ids::PROFILE_BUFFER_FULL);
                self.emit(
                    events,
                    exec_id,
                    CommandState::Error(ids::PROFILE_BUFFER_FULL),
                );
            } else {
                // T15
                self.done = false;
                let prep = if self.path_hold {
                    if let Some(r) = self.running.as_deref_mut() {
                        if let Some(id) = exec_id {
                            // The resume edge's id completes with the held profile.
                            events.push(CommandEvent {
                                id,
                                state: CommandState::Busy,
                            });
                            match r.job.id {
                                None => r.job.id = Some(id),
                                Some(held) => self.resume_ids.push((held, id)),
                            }
                        }
                    }
                    Prep::Resume
                } else {
                    let job = self.make_job(self.inputs.set_target, exec_id);
                    self.emit(events, exec_id, CommandState::Busy);
                    Prep::New(Box::new(job))
                };
                self.prep = Some((self.cfg.path_prep_cycles, prep));
                self.set_state(TmState::PreparingPath);
                self.preparing(events);
                return;
            }
        }
        if (e.jog_pos || e.jog_neg) && self.inputs.select_axis != 0 {
            // T7 / T8 (and T23 with a held path)
            if !self.axes_enabled() {
                self.set_warning(ids::AXES_NOT_ENABLED);
            } else if e.jog_pos && !self.inputs.jog_neg {
                if !self.start_jog(true, false) {
                    self.set_warning(ids::COMMAND_NOT_ALLOWED);
                }
            } else if e.jog_neg && !self.inputs.jog_pos && !self.start_jog(false, false) {
                self.set_warning(ids::COMMAND_NOT_ALLOWED);
            }
            if self.state != TmState::Ready {
                return;
            }
        }
        if e.home {
            // T10
            if self.axes_enabled() {
                self.start_homing(home_id, events);
                return;
            }
            self.ignored_edge(events, home_id);
        }
        if e.abort {
            // T22
            if self.path_hold {
                self.discard_all(events, CommandState::Aborted);
                if matches!(self.motion, Motion::Running) {
                    self.motion = Motion::Still;
                }
            } else {
                self.ignored_edge(events, None);
            }
        }
        if self.inputs.service.move_abs && !self.prev.service.move_abs && self.axes_enabled() {
            // T13
            let s = self.inputs.service;
            let lim = Limits {
                velocity: s.vel,
                acceleration: s.acc,
                deceleration: s.dec,
                jerk: s.jerk,
            };
            let start = State1::at_rest(self.axis_value(s.axis as usize));
            if let Ok(profile) = Profile1::to_position(start, s.pos, 0.0, &lim) {
                self.motion = Motion::Service(ServiceRun {
                    axis: s.axis,
                    profile,
                    t: 0.0,
                });
                self.done = false;
                self.in_target = false;
                self.in_position_target = None;
                self.set_state(TmState::Service);
            }
        }
        // Bound to a workpiece that reaches the end of the working area: lift to park (§15.4).
        if let Motion::Bound {
            frame,
            wp_x0,
            wp_s0,
            ..
        } = &self.motion
        {
            let b = &self.belts[frame.belt - 1];
            if wp_x0 + (b.axis.position - wp_s0) > b.par.upper_sync_limit && self.axes_enabled() {
                let n = frame.belt;
                self.set_warning(ids::SYNC_LIMIT_EXCEEDED);
                let job = Job {
                    id: None,
                    par: self.par.clone(),
                    target: Target::ParkOnly(n),
                    role: Role::External,
                    set_target: 0,
                    mode: 0,
                    preferred_wp: None,
                };
                match self.start_job(job) {
                    Ok(r) => {
                        self.running = Some(Box::new(r));
                        self.motion = Motion::Running;
                        self.set_state(TmState::MovePp);
                    }
                    Err(err) => self.raise_error(err, None, events),
                }
            }
        }
    }

    pub(super) fn mark_active(&mut self, events: &mut Vec<CommandEvent>) {
        if let Some(r) = self.running.as_deref_mut() {
            if !r.active_emitted {
                r.active_emitted = true;
                if let Some(id) = r.job.id {
                    events.push(CommandEvent {
                        id,
                        state: CommandState::Active,
                    });
                }
            }
        }
    }

    /// T24: an execute edge in MOVE_PP appends a profile (§8).
    pub(super) fn append(&mut self, events: &mut Vec<CommandEvent>, id: Option<CmdId>) {
        if self.profile_in_preparation() {
            self.set_warning(ids::PROFILE_BUFFER_FULL);
            self.emit(events, id, CommandState::Error(ids::PROFILE_BUFFER_FULL));
            return;
        }
        let mode = self.par.tracking_mode;
        let running_mode = self.running.as_deref().map_or(0, |r| r.job.mode);
        if running_mode > 0 || mode > 0 {
            if mode == running_mode {
                // The same endless mode again: nothing to change.
                self.ignored_edge(events, id);
                return;
            }
            // A new mode takes over after the current leg (§11); mode 0 brings its target.
            self.emit(events, id, CommandState::Busy);
            if mode == 0 {
                let job = self.make_job(self.inputs.set_target, id);
                self.append_prep = Some((self.cfg.path_prep_cycles, job));
                self.next_mode = Some((0, None));
            } else {
                self.next_mode = Some((mode, id));
            }
            return;
        }
        let job = self.make_job(self.inputs.set_target, id);
        self.emit(events, id, CommandState::Busy);
        self.append_prep = Some((self.cfg.path_prep_cycles, job));
    }

    /// Continues a held path (§9.2, §9.4): from the hold point, or re-planned to the same target.
    pub(super) fn resume(&mut self, events: &mut Vec<CommandEvent>) {
        let Some(mut r) = self.running.take() else {
            self.set_state(TmState::Ready);
            return;
        };
        if r.job.mode > 0 {
            // §11: a resumed leg restarts the loop with the currently selected mode (0 ends it).
            r.job.mode = self.par.tracking_mode;
        }
        let moved = (0..7).any(|q| (self.pose[q] - r.hold_pose[q]).abs() > 1e-9);
        if moved && !r.replan {
            // Jogged away from the hold point (§9.2): straight to the next profile point, then on.
            let par = r.job.par.clone();
            match &mut r.phase {
                Phase::Path { run, .. } => match self.path_after_jog(run, &par) {
                    Some(nr) => **run = nr,
                    None => r.replan = true,
                },
                _ => r.replan = true,
            }
            if !r.replan {
                r.gripper.active = false;
                self.running = Some(r);
                self.motion = Motion::Running;
                self.path_hold = false;
                self.start_next_cycle = self.state == TmState::PreparingPath;
                self.set_state(TmState::MovePp);
                self.mark_active(events);
                return;
            }
        }
        if r.replan {
            // Re-plan the complete profile from the current pose to the same target.
            self.release_reservation(&r);
            let mut job = r.job.clone();
            job.preferred_wp = match &r.phase {
                Phase::Path { workpiece, .. } | Phase::Dwell { workpiece, .. } => *workpiece,
                _ => None,
            };
            match self.start_job(job) {
                Ok(mut nr) => {
                    nr.active_emitted = r.active_emitted;
                    nr.gripper.active = false;
                    r = Box::new(nr);
                }
                Err(err) => {
                    self.emit(events, r.job.id, CommandState::Error(err));
                    self.raise_error(err, None, events);
                    return;
                }
            }
        } else if let Phase::Path { run, .. } = &mut r.phase {
            run.resume();
        }
        self.running = Some(r);
        self.motion = Motion::Running;
        self.path_hold = false;
        self.start_next_cycle = self.state == TmState::PreparingPath;
        self.set_state(TmState::MovePp);
        self.mark_active(events);
    }
}
