//! A group's path motion (plcopen_platform.md §5): MC_MoveLinear* and MC_MovePath jobs, their
//! limits, the stops (MC_GroupHalt, MC_GroupStop, error stops with the reaction class) and
//! the group's cycle.

use super::*;

impl GroupCx<'_> {
    pub(super) fn move_linear(
        &mut self,
        g: usize,
        c: MoveLinear,
        relative: bool,
    ) -> Result<GroupCallReply, Rejection> {
        let (fb, kind) = if relative {
            ("MC_MoveLinearRelative", GroupFbKind::MoveLinearRelative)
        } else {
            ("MC_MoveLinearAbsolute", GroupFbKind::MoveLinearAbsolute)
        };
        let gname = &self.groups.list[g].name;
        let field = if relative { "Distance" } else { "Position" };
        for (k, v) in c.position.iter().enumerate() {
            finite(gname, fb, &format!("{field}[{k}]"), *v)?;
        }
        let d = Dyn {
            velocity: c.velocity,
            acceleration: c.acceleration,
            deceleration: c.deceleration,
            jerk: c.jerk,
        };
        dynamics(gname, fb, Some(c.velocity), &d)?;
        let n = self.groups.list[g].members.len();
        if c.position.len() != n {
            return Err(invalid(
                gname,
                fb,
                format!(
                    "{field} has {} values, the group has {n} axes",
                    c.position.len()
                ),
            ));
        }
        only_aborting(gname, fb, c.buffer_mode)?;
        if c.transition_mode != TransitionMode::None {
            return Err(reject(
                ERR_SIM_NOT_IMPLEMENTED,
                format!(
                    "group '{gname}': {fb}: TransitionMode {:?} is not implemented (only TMNone)",
                    c.transition_mode
                ),
            ));
        }
        self.group_admit(g, GroupFbClass::Move, fb)?;
        self.members_ready(g, fb)?;
        let target: Vec<f64> = if relative {
            self.member_set(g)
                .iter()
                .zip(&c.position)
                .map(|(p, d)| p + d)
                .collect()
        } else {
            c.position
        };
        self.check_soft_limits(g, fb, &target)?;
        self.group_safety_check(g, fb, !relative, &target, c.velocity)?;
        let id = self.group_instance(g, kind, CommandState::Active);
        self.group_start_move(g, id, VecDeque::from([target]), d);
        Ok(Self::group_tracked(id))
    }

    /// The current path state: (start, dir, s-state) of the running job, if moving.
    pub(super) fn path_state(&self, g: usize) -> Option<(State1, Vec<f64>)> {
        let j = self.groups.list[g].job.as_ref()?;
        let s = j.profile.at(j.t);
        Some((s, j.dir.clone()))
    }

    /// Ends the running owner (CommandAborted) when a newer command takes over.
    pub(super) fn group_take_over(&mut self, g: usize) {
        if let Some(owner) = self.groups.list[g].job.as_ref().and_then(|j| j.owner) {
            self.groups.set(self.fbs, owner, CommandState::Aborted);
        }
        if let Some(j) = self.groups.list[g].job.as_mut() {
            j.owner = None;
        }
    }

    /// Starts (or takes over with) a move through `queue`.
    pub(super) fn group_start_move(
        &mut self,
        g: usize,
        id: CmdId,
        mut queue: VecDeque<Vec<f64>>,
        d: Dyn,
    ) {
        self.group_take_over(g);
        let members = self.members(g);
        let here = self.member_set(g);
        let factor = self.groups.list[g].factor();
        if let Some((s, dir)) = self
            .path_state(g)
            .filter(|(s, _)| s.vel.abs() > V_REST || s.acc.abs() > V_REST)
        {
            // Moving: continue along a parallel same-direction line, else stop first.
            let first = queue.front().cloned().unwrap_or_else(|| here.clone());
            let (ndir, len) = unit(&here, &first);
            let dot: f64 = ndir.iter().zip(&dir).map(|(a, b)| a * b).sum();
            if queue.len() == 1 && len > 0.0 && dot > 1.0 - 1e-9 && s.vel > 0.0 {
                let l = self.group_limits(&members, &ndir, &d);
                let l = Limits {
                    velocity: (l.velocity * factor).max(1e-9),
                    ..l
                };
                let start = State1 {
                    pos: 0.0,
                    vel: s.vel,
                    acc: s.acc,
                };
                if let Ok(p) = Profile1::to_position(start, len, 0.0, &l) {
                    self.groups.list[g].job = Some(PathJob {
                        owner: Some(id),
                        kind: PathKind::Move,
                        start: here,
                        dir: ndir,
                        profile: p,
                        t: 0.0,
                        dynamics: d,
                        queue: VecDeque::new(),
                        paused: factor <= 0.0,
                        end: first,
                    });
                    return;
                }
            }
            // Stop path-true along the old direction with the new deceleration.
            let stop = self.stop_profile(&members, &dir, s, &d);
            let end: Vec<f64> = here
                .iter()
                .zip(&dir)
                .map(|(p, u)| p + u * (stop.end().pos - s.pos))
                .collect();
            self.groups.list[g].job = Some(PathJob {
                owner: Some(id),
                kind: PathKind::Move,
                start: here.iter().zip(&dir).map(|(p, u)| p - u * s.pos).collect(),
                dir,
                profile: stop,
                t: 0.0,
                dynamics: d,
                queue,
                paused: false,
                end,
            });
            return;
        }
        let first = queue.pop_front().unwrap_or_else(|| here.clone());
        let job = self.plan_segment(g, Some(id), here, first, queue, d);
        self.groups.list[g].job = Some(job);
    }

    /// Path limits with the safety caps of the members (R-SAF-5 T1 speed, R-SAF-6 reduced
    /// speed of non-referenced axes): `v_path ≤ cap_i / |u_i|`.
    pub(super) fn group_limits(&self, members: &[usize], dir: &[f64], d: &Dyn) -> Limits {
        let mut l = path_limits(self.axes, members, dir, d);
        for (k, &ax) in members.iter().enumerate() {
            let u = dir.get(k).copied().unwrap_or(0.0).abs();
            let cap = self.profile.velocity_cap(ax);
            if u > 1e-12 && cap.is_finite() {
                l.velocity = l.velocity.min(cap / u);
            }
        }
        l
    }

    /// The profile's safety checks of a group order (R-SAF-1a, R-SAF-6; see
    /// [`GroupProfile::check_group_motion`]) along the line from the members' set positions
    /// to `target`.
    pub(super) fn group_safety_check(
        &mut self,
        g: usize,
        fb: &str,
        absolute: bool,
        target: &[f64],
        velocity: f64,
    ) -> Result<(), Rejection> {
        let members = self.members(g);
        let here = self.member_set(g);
        let (dir, _) = unit(&here, target);
        let name = self.groups.list[g].name.clone();
        self.profile.check_group_motion(
            self.axes, self.fbs, &name, fb, &members, absolute, &dir, velocity,
        )
    }

    /// A rest-to-rest segment from `from` to `to`.
    pub(super) fn plan_segment(
        &self,
        g: usize,
        owner: Option<CmdId>,
        from: Vec<f64>,
        to: Vec<f64>,
        queue: VecDeque<Vec<f64>>,
        d: Dyn,
    ) -> PathJob {
        let members = self.members(g);
        let factor = self.groups.list[g].factor();
        let (dir, len) = unit(&from, &to);
        let l = self.group_limits(&members, &dir, &d);
        let profile = if len <= 0.0 || factor <= 0.0 {
            Profile1::hold(State1::at_rest(0.0))
        } else {
            let l = Limits {
                velocity: l.velocity * factor,
                ..l
            };
            Profile1::to_position(State1::at_rest(0.0), len, 0.0, &l)
                .unwrap_or_else(|_| Profile1::hold(State1::at_rest(0.0)))
        };
        PathJob {
            owner,
            kind: PathKind::Move,
            start: from,
            dir,
            profile,
            t: 0.0,
            dynamics: d,
            queue,
            paused: factor <= 0.0 && len > 0.0,
            end: to,
        }
    }

    /// A path-true stop from path state `s` along `dir` with `d`'s deceleration and jerk.
    pub(super) fn stop_profile(
        &self,
        members: &[usize],
        dir: &[f64],
        s: State1,
        d: &Dyn,
    ) -> Profile1 {
        let l = path_limits(self.axes, members, dir, d);
        let l = Limits {
            velocity: l.velocity.max(s.vel.abs()).max(1e-9),
            acceleration: l.acceleration.max(l.deceleration),
            ..l
        };
        Profile1::stopping(s, &l).unwrap_or_else(|_| Profile1::hold(State1::at_rest(s.pos)))
    }

    /// Quick stop on the path (reaction class 2): each member's fast limits over its
    /// direction cosine, as `path_limits` does with the normal ones.
    pub(super) fn quick_stop_profile(&self, members: &[usize], dir: &[f64], s: State1) -> Profile1 {
        let mut l = Limits {
            velocity: f64::INFINITY,
            acceleration: f64::INFINITY,
            deceleration: f64::INFINITY,
            jerk: f64::INFINITY,
        };
        for (k, &i) in members.iter().enumerate() {
            let u = dir.get(k).copied().unwrap_or(0.0).abs();
            if u > 1e-12 {
                let f = self.axes[i].fast_limits();
                l.velocity = l.velocity.min(f.velocity / u);
                l.deceleration = l.deceleration.min(f.deceleration / u);
                l.jerk = l.jerk.min(f.jerk / u);
            }
        }
        let finite = |x: f64| if x.is_finite() { x } else { 1.0 };
        let l = Limits {
            velocity: finite(l.velocity).max(s.vel.abs()).max(1e-9),
            acceleration: finite(l.deceleration),
            deceleration: finite(l.deceleration),
            jerk: finite(l.jerk),
        };
        Profile1::stopping(s, &l).unwrap_or_else(|_| Profile1::hold(State1::at_rest(s.pos)))
    }

    /// The running path job `j` replaced by the stop `stop` from its current state, on the
    /// same line.
    pub(super) fn path_stop_job(
        &self,
        g: usize,
        j: PathJob,
        stop: Profile1,
        owner: Option<CmdId>,
        kind: PathKind,
    ) -> PathJob {
        let here = self.member_set(g);
        let origin = stop.at(0.0).pos;
        let start: Vec<f64> = here
            .iter()
            .zip(&j.dir)
            .map(|(p, u)| p - u * origin)
            .collect();
        let end = start
            .iter()
            .zip(&j.dir)
            .map(|(p, u)| p + u * stop.end().pos)
            .collect();
        PathJob {
            owner,
            kind,
            start,
            dir: j.dir,
            profile: stop,
            t: 0.0,
            dynamics: j.dynamics,
            queue: VecDeque::new(),
            paused: false,
            end,
        }
    }

    /// MC_GroupHalt / MC_GroupStop: path-true stop of the running motion (or Done at rest).
    pub(super) fn group_start_stop(&mut self, g: usize, id: CmdId, kind: PathKind, d: Dyn) {
        self.group_take_over(g);
        let members = self.members(g);
        let here = self.member_set(g);
        let job = match self.groups.list[g].job.take() {
            Some(j) => {
                let s = j.profile.at(j.t);
                let stop = self.stop_profile(&members, &j.dir, s, &d);
                PathJob {
                    dynamics: d,
                    ..self.path_stop_job(g, j, stop, Some(id), kind)
                }
            }
            None => PathJob {
                owner: Some(id),
                kind,
                start: here.clone(),
                dir: vec![0.0; here.len()],
                profile: Profile1::hold(State1::at_rest(0.0)),
                t: 0.0,
                dynamics: d,
                queue: VecDeque::new(),
                paused: false,
                end: here,
            },
        };
        self.groups.list[g].job = Some(job);
    }

    /// MC_GroupSetOverride changed the factor: replan the running move from its path state.
    pub(super) fn group_replan_override(&mut self, g: usize) {
        let members = self.members(g);
        let factor = self.groups.list[g].factor();
        let Some(j) = self.groups.list[g].job.as_ref() else {
            return;
        };
        if j.kind != PathKind::Move {
            return;
        }
        let s = j.profile.at(j.t);
        let len: f64 = j
            .end
            .iter()
            .zip(&j.start)
            .zip(&j.dir)
            .map(|((e, st), u)| (e - st) * u)
            .sum();
        let l = self.group_limits(&members, &j.dir, &j.dynamics);
        let profile = if factor <= 0.0 {
            self.stop_profile(&members, &j.dir, s, &j.dynamics)
        } else {
            let l = Limits {
                velocity: (l.velocity * factor).max(1e-9),
                ..l
            };
            match Profile1::to_position(s, len, 0.0, &l) {
                Ok(p) => p,
                Err(_) => return,
            }
        };
        if let Some(j) = self.groups.list[g].job.as_mut() {
            // Keep the path coordinate: the new profile starts at s.pos.
            j.profile = profile;
            j.t = 0.0;
            j.paused = factor <= 0.0;
        }
    }

    /// Ends the group motion and hands the members back (disable, ungroup): owners
    /// CommandAborted, moving members brake on their own with AxisDec/AxisJerk.
    pub fn group_abort_motion(&mut self, g: usize, abort_lock: bool) {
        self.group_take_over(g);
        self.groups.list[g].job = None;
        if abort_lock {
            if let Some(l) = self.groups.list[g].lock.take() {
                if !l.done {
                    self.groups.set(self.fbs, l.owner, CommandState::Aborted);
                }
            }
        }
        self.release_members(g, false);
    }

    /// Members no longer driven by the group; moving ones get a stop ramp.
    pub(super) fn release_members(&mut self, g: usize, fast: bool) {
        for ax in self.members(g) {
            let a = &mut self.axes[ax];
            if !a.group_motion {
                continue;
            }
            a.group_motion = false;
            if a.moving() && a.error_id.is_none() && a.controller_on {
                let l = if fast {
                    a.fast_limits()
                } else {
                    a.default_limits()
                };
                let profile = a.plan_stop(&l);
                let stop = profile.end().pos;
                a.start_job(Job::internal(JobKind::FastStop, profile, stop, l));
            }
        }
    }

    /// One cycle of every group: error latch, path interpolation (members' set values).
    /// Runs before the axes step (they then compute actual values and monitoring).
    pub fn groups_step(&mut self, dt: f64) {
        for k in 0..self.groups.instant_done.len() {
            let id = self.groups.instant_done[k];
            self.groups.set(self.fbs, id, CommandState::Done);
        }
        self.groups.instant_done.clear();
        let hold = self.profile.feed_hold();
        for g in 0..self.groups.list.len() {
            self.groups.list[g].slot = false;
            if self.groups.list[g].held != hold {
                self.groups.list[g].held = hold;
                self.group_replan_override(g);
            }
            self.group_step(g, dt);
        }
    }

    pub(super) fn group_step(&mut self, g: usize, dt: f64) {
        let grp = &self.groups.list[g];
        if grp.members.is_empty() {
            return;
        }
        // Member error → GROUP_ERROR_STOP (latched until MC_GrpReset).
        let member_error = grp.axes().any(|i| !self.axes[i].error_id.is_none());
        if member_error && !grp.disabled && grp.error.is_none() {
            self.groups.list[g].error = ERR_PLC_AX_MC;
            let owner = self.groups.list[g].job.as_ref().and_then(|j| j.owner);
            let lock = self.groups.list[g].lock.take().map(|l| l.owner);
            for id in owner.into_iter().chain(lock) {
                self.groups
                    .set(self.fbs, id, CommandState::Error(ERR_PLC_AX_MC));
            }
            if let Some(j) = self.groups.list[g].job.as_mut() {
                j.owner = None;
            }
            // Every member brakes with the group's error reaction, on the path while all
            // members are powered; otherwise each stops on its own (fast limits).
            let powered = self.groups.list[g]
                .axes()
                .all(|i| self.axes[i].controller_on && self.axes[i].status);
            match self.groups.list[g].job.take() {
                Some(j) if powered => {
                    let members = self.members(g);
                    let reaction = members
                        .iter()
                        .filter(|&&i| !self.axes[i].error_id.is_none())
                        .map(|&i| self.axes[i].error_reaction)
                        .max()
                        .unwrap_or(0);
                    let s = j.profile.at(j.t);
                    let stop = if reaction == 1 {
                        // Class 1: the programmed deceleration of the running motion.
                        self.stop_profile(&members, &j.dir, s, &j.dynamics)
                    } else {
                        // Class 2 and errors that are no MC message: quick stop.
                        self.quick_stop_profile(&members, &j.dir, s)
                    };
                    let job = self.path_stop_job(g, j, stop, None, PathKind::ErrorStop);
                    self.groups.list[g].job = Some(job);
                }
                _ => self.release_members(g, true),
            }
            return;
        }
        // A member lost power (MC_Power off): the motion is aborted, the group is disabled.
        let powered = self.groups.list[g]
            .axes()
            .all(|i| self.axes[i].controller_on && self.axes[i].status);
        if !powered && self.groups.list[g].job.is_some() {
            self.group_abort_motion(g, true);
            return;
        }
        // MC_GroupStop lock released at rest with Execute FALSE.
        if let Some(l) = self.groups.list[g].lock {
            if l.done && !l.execute && self.groups.list[g].job.is_none() {
                self.groups.list[g].lock = None;
            }
        }
        // Interpolation (no alloc, no lock): every member on the line at s(t).
        let grp = &mut self.groups.list[g];
        let Some(job) = grp.job.as_mut() else {
            grp.path_vel = 0.0;
            grp.path_acc = 0.0;
            return;
        };
        job.t += dt;
        let s = job.profile.at(job.t);
        let ended = job.t >= job.profile.duration() && !job.paused;
        for (k, &(_, ax)) in grp.members.iter().enumerate() {
            let a = &mut self.axes[ax];
            let u = job.dir[k];
            a.job = None;
            a.group_motion = true;
            a.set = State1 {
                pos: job.start[k] + u * s.pos,
                vel: u * s.vel,
                acc: u * s.acc,
            };
            a.target_pos = job.end[k];
        }
        grp.path_vel = s.vel;
        grp.path_acc = s.acc;
        if !ended {
            return;
        }
        let members = self.members(g);
        // Segment end: exactly at its end point, at rest.
        let Some(mut job) = self.groups.list[g].job.take() else {
            return;
        };
        let end_pos = job.profile.end().pos;
        for (k, &ax) in members.iter().enumerate() {
            let a = &mut self.axes[ax];
            let p = job.start[k] + job.dir[k] * end_pos;
            a.set = State1::at_rest(p);
            a.target_pos = p;
            a.last_target = Some(p);
        }
        self.groups.list[g].path_vel = 0.0;
        self.groups.list[g].path_acc = 0.0;
        if let Some(next) = job.queue.pop_front() {
            let here = self.member_set(g);
            let queue = std::mem::take(&mut job.queue);
            let nj = self.plan_segment(g, job.owner, here, next, queue, job.dynamics);
            self.groups.list[g].job = Some(nj);
            return;
        }
        for &ax in &members {
            self.axes[ax].group_motion = false;
        }
        match job.kind {
            PathKind::ErrorStop => {}
            PathKind::Move | PathKind::Halt => {
                if let Some(id) = job.owner {
                    self.groups.set(self.fbs, id, CommandState::Done);
                }
            }
            PathKind::Stop => {
                if let Some(l) = self.groups.list[g].lock.as_mut() {
                    l.done = true;
                    let (owner, execute) = (l.owner, l.execute);
                    self.groups.set(self.fbs, owner, CommandState::Done);
                    if !execute {
                        self.groups.list[g].lock = None;
                    }
                }
            }
        }
    }
}
