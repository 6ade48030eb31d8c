//! The CA group cycle (collision_avoidance.md §4.2 transitions driven by the axes, §8.3
//! processing order, §8.5/§8.6 glue to the planner). No alloc in steady state, no lock.

use super::*;
impl CaGroups {
    // ------------------------------------------------------------------ cycle

    /// One cycle of every group (§8.3). Runs before the single-axis step. No alloc in steady
    /// state (scratch vectors are reused), no lock.
    pub fn step(&mut self, dt: f64, axes: &mut [Axis], fbs: &mut Handshake) {
        for i in 0..self.instant_done.len() {
            let id = self.instant_done[i];
            self.set_state(fbs, id, CommandState::Done);
        }
        self.instant_done.clear();
        for g in 0..self.groups.len() {
            self.step_group(g, dt, axes, fbs);
        }
    }

    pub(super) fn raise_group_error(
        &mut self,
        g: usize,
        id: ErrorId,
        axes: &mut [Axis],
        fbs: &mut Handshake,
    ) {
        let how = CommandState::Error(id);
        self.end_group_blocks(fbs, g, how);
        for k in 0..self.groups[g].n() {
            self.end_member(fbs, g, k, how);
            let m = &mut self.groups[g].members[k];
            let ad = m.dynamics;
            if axes[m.axis].moving() {
                m.job = Job::Brake {
                    req: Request {
                        owner: None,
                        goal: Goal::Brake,
                        dy: Dyn {
                            v: ad.max_v,
                            a: ad.max_a,
                            d: ad.max_d,
                            j: ad.max_j,
                        },
                        gap: m.last_gap,
                        mode: GapControlMode::GroupDefault,
                        continuous_update: false,
                        dyn_path: None,
                    },
                };
            }
        }
        let gr = &mut self.groups[g];
        gr.error_id = id;
        gr.state = GroupState::GroupErrorStop;
    }

    pub(super) fn step_group(&mut self, g: usize, dt: f64, axes: &mut [Axis], fbs: &mut Handshake) {
        use GroupState::*;
        // Transitions driven by the axes (T4, T5, T13, T14).
        let axis_error = self.groups[g]
            .members
            .iter()
            .map(|m| axes[m.axis].error_id)
            .find(|e| !e.is_none());
        let all_ready = self.groups[g]
            .members
            .iter()
            .all(|m| loop_closed(&axes[m.axis]));
        match (self.groups[g].state, axis_error) {
            (GroupDisabled, Some(e)) => {
                self.groups[g].error_id = e;
                self.groups[g].state = GroupErrorDisabled;
            }
            (GroupStandby | GroupMoving | GroupStopping | GroupNotReady, Some(e)) => {
                self.raise_group_error(g, e, axes, fbs)
            }
            (GroupNotReady, None) if all_ready && self.groups[g].n() > 0 => {
                self.groups[g].state = GroupStandby
            }
            (GroupStandby | GroupMoving, None) if !all_ready => {
                // T5: the axis without loop freezes (its set values are already 0).
                self.raise_group_error(g, err::AXIS_NOT_READY, axes, fbs)
            }
            _ => {}
        }
        let gr = &mut self.groups[g];
        if !gr.enabled() {
            // Disabled: single-axis control; keep the published gaps current.
            gr.init_all_gaps(axes);
            return;
        }
        // Override ramp (§1.11).
        if gr.ovr_actual != gr.ovr_target {
            let step = gr.ovr_rate * dt;
            gr.ovr_actual = if (gr.ovr_target - gr.ovr_actual).abs() <= step {
                gr.ovr_target
            } else {
                gr.ovr_actual + step * (gr.ovr_target - gr.ovr_actual).signum()
            };
        }
        if gr.state == GroupNotReady {
            return;
        }
        if !matches!(self.groups[g].state, GroupStopping | GroupErrorStop) {
            self.groups[g].plan_establishing();
        } else {
            for m in &mut self.groups[g].members {
                m.retreat = 0.0;
            }
        }
        self.plan_cycle(g, dt, axes);
        self.finish_jobs(g, axes, fbs);
        // Group blocks and T8/T10.
        let standing = self.groups[g].all_standing(axes);
        let busy = self.groups[g].busy();
        if standing {
            if let Some(h) = self.groups[g].halt {
                if !busy {
                    self.groups[g].halt = None;
                    self.set_state(fbs, h, CommandState::Done);
                }
            }
            if let Some(s) = self.groups[g].stop {
                if !self.groups[g].stop_done {
                    self.groups[g].stop_done = true;
                    self.set_state(fbs, s, CommandState::Done);
                }
                let exec = self.instances.get(&s).is_some_and(|i| i.execute);
                if !exec {
                    self.groups[g].stop = None;
                    self.groups[g].stop_done = false;
                    self.groups[g].state = GroupStandby;
                }
            }
        }
        let gr = &mut self.groups[g];
        match gr.state {
            GroupStandby if busy || !standing => gr.state = GroupMoving,
            GroupMoving if !busy && standing => gr.state = GroupStandby,
            _ => {}
        }
        // Diagnostics (§8.7).
        for k in 0..gr.n() {
            let target = gr.eff_gap(k);
            let gap = gr.gap_measured(k, axes);
            let m = &mut gr.members[k];
            if gap.is_finite() {
                m.min_margin = m.min_margin.min(gap - target);
            }
        }
    }

    /// Ends reached positions (Done), finished brakes, activates buffered commands.
    pub(super) fn finish_jobs(&mut self, g: usize, axes: &mut [Axis], fbs: &mut Handshake) {
        for k in 0..self.groups[g].n() {
            let ax = self.groups[g].members[k].axis;
            let s = axes[ax].set;
            let at_rest = s.vel == 0.0 && s.acc == 0.0;
            if let Job::Gear { req, gear } = self.groups[g].members[k].job {
                let m = &mut self.groups[g].members[k];
                if gear.failed {
                    // Late/Slow: no feasible sync profile (§5.5.3).
                    m.job = if at_rest {
                        Job::Idle
                    } else {
                        Job::Brake {
                            req: Request {
                                owner: None,
                                goal: Goal::Brake,
                                ..req
                            },
                        }
                    };
                    if let Some(id) = req.owner {
                        self.set_state(fbs, id, CommandState::Error(err::SLAVE_CANNOT_SYNC));
                    }
                } else if gear.in_sync {
                    // A buffered command starts when the coupling first becomes InSync.
                    if let Some(p) = m.pending.take() {
                        m.job = activate(p, s.pos);
                        if let Some(id) = req.owner {
                            self.set_state(fbs, id, CommandState::Aborted);
                        }
                        if let Some(id) = p.owner {
                            self.set_state(fbs, id, CommandState::Active);
                        }
                    }
                }
                continue;
            }
            if !at_rest {
                continue;
            }
            let job = self.groups[g].members[k].job;
            let finished = match job {
                Job::Position { target, .. } => {
                    if (s.pos - target).abs() <= EPS {
                        let dx = target - s.pos;
                        axes[ax].set.pos = target;
                        self.groups[g].shift(k, dx);
                        true
                    } else {
                        false
                    }
                }
                Job::Brake { .. } => true,
                Job::Idle | Job::Gear { .. } => false,
            };
            if finished {
                let m = &mut self.groups[g].members[k];
                if let Some(r) = job.req() {
                    if r.mode != GapControlMode::None {
                        m.last_gap = r.gap;
                    }
                }
                m.job = Job::Idle;
                axes[ax].target_pos = axes[ax].set.pos;
                if let Some(id) = job.owner() {
                    self.set_state(fbs, id, CommandState::Done);
                }
                if let Some(p) = self.groups[g].members[k].pending.take() {
                    if let Some(id) = p.owner {
                        self.set_state(fbs, id, CommandState::Active);
                    }
                    self.groups[g].members[k].job = activate(p, axes[ax].set.pos);
                }
            }
        }
    }

    /// Runs the planner for every member in the order of §8.3.
    pub(super) fn plan_cycle(&mut self, g: usize, dt: f64, axes: &mut [Axis]) {
        let gr = &mut self.groups[g];
        let n = gr.n();
        if n == 0 {
            return;
        }
        // Front-to-back order; on a ring from the axis with the largest gap (ties: lowest ident).
        let mut start = 0;
        if gr.cfg.rail_is_ring && n > 1 {
            for k in 1..n {
                let (a, b) = (&gr.members[k], &gr.members[start]);
                if a.gap > b.gap || (a.gap == b.gap && a.ident < b.ident) {
                    start = k;
                }
            }
        }
        let mut order = std::mem::take(&mut gr.order);
        let mut back = std::mem::take(&mut gr.back);
        order.clear();
        back.clear();
        for i in 0..n {
            let k = (start + i) % n;
            gr.members[k].updated = false;
            let m = &gr.members[k];
            if frame_sign(axes[m.axis].set, &m.job, m.retreat) < 0.0 {
                back.push(k);
            } else {
                order.push(k);
            }
        }
        order.extend(back.iter().rev());
        for &k in &order {
            gr.step_member(k, dt, axes);
        }
        gr.order = order;
        gr.back = back;
    }
}

/// The travel frame of an axis: +1 forward, −1 backward (§8.5, mirrored).
pub(super) fn frame_sign(s: State1, job: &Job, retreat: f64) -> f64 {
    if s.vel > 0.0 {
        1.0
    } else if s.vel < 0.0 {
        -1.0
    } else if s.acc > 0.0 {
        1.0
    } else if s.acc < 0.0 || retreat > ESTABLISH_MIN {
        -1.0
    } else {
        match job {
            Job::Position { target, .. } if *target < s.pos => -1.0,
            Job::Gear { gear, .. } if gear.target < s.pos => -1.0,
            _ => 1.0,
        }
    }
}

/// C4-Fast in the forward frame (§8.6) for a predecessor at `x` (minus the gap) with velocity
/// `v ≥ 0` and maximum deceleration `d`: `x' ≤ x̂` (its predicted position, when its state is
/// from the start of the cycle) and `StopPoint ≤ x + v²/(2d)`; `lead` for the sampled form.
fn fast_bound(x: f64, v: f64, d: f64, updated: bool, dt: f64) -> Bound {
    let v = v.max(0.0);
    let lead = Lead {
        x,
        v,
        d,
        t0: if updated { 0.0 } else { dt },
    };
    Bound {
        pos_bound: lead.at(lead.t0),
        stop_bound: x + v * v / (2.0 * d),
        lead: Some(lead),
    }
}

pub(super) fn moving_back(s: State1) -> bool {
    s.vel < 0.0 || (s.vel == 0.0 && s.acc < 0.0)
}

pub(super) fn moving_fwd(s: State1) -> bool {
    s.vel > 0.0 || (s.vel == 0.0 && s.acc > 0.0)
}

pub(super) fn kin(s: State1) -> Kin {
    Kin {
        x: s.pos,
        v: s.vel,
        a: s.acc,
    }
}

pub(super) fn activate(req: Request, x: f64) -> Job {
    match req.goal {
        Goal::Absolute(t) => Job::Position { req, target: t },
        Goal::Relative(d) => Job::Position { req, target: x + d },
        Goal::RelativeOffset(d, p) => Job::Position {
            req,
            target: p.from_offset(p.to_offset(x) + d),
        },
        Goal::Brake => Job::Brake { req },
        Goal::Gear(gear) => Job::Gear { req, gear },
    }
}

impl CaGroup {
    /// Member `k` moved by `dx`: its own gap shrinks, its successor's grows.
    pub(super) fn shift(&mut self, k: usize, dx: f64) {
        if dx == 0.0 {
            return;
        }
        if self.members[k].gap.is_finite() {
            self.members[k].gap -= dx;
        }
        if let Some(s) = self.succ(k) {
            self.members[s].gap += dx;
        }
    }

    /// The pair constraint C4 of member `k` in frame `sg` (§1.5, §8.6), in Fast mode the
    /// neighbour's maximum deceleration (else +inf) and whether that neighbour moves (toward
    /// or away from the axis: then the axis' deceleration is capped by it, §8.6).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn c4_bound(
        &self,
        k: usize,
        s: State1,
        sg: f64,
        own_mode: GapControlMode,
        establishing: bool,
        dt: f64,
        axes: &[Axis],
    ) -> (Option<Bound>, f64, bool) {
        let mut fast_dmax = f64::INFINITY;
        let mut lead_moving = false;
        let c4 = if own_mode == GapControlMode::None {
            None
        } else if sg > 0.0 {
            self.pred(k).map(|l| {
                let g = self.eff_gap(k);
                let ls = axes[self.members[l].axis].set;
                let xl = s.pos + self.members[k].gap;
                let dl = self.members[l].dynamics.max_d;
                let y = self.comp_y(k);
                if y > 0.0 {
                    // Compensated successor: the gap lies on its offset path; Standard rule
                    // with the predecessor mapped to that path (§5.9).
                    let x = if moving_back(ls) {
                        stop_point_back(
                            Kin { x: xl, ..kin(ls) },
                            self.members[l].d_b,
                            self.members[l].j_b,
                        )
                    } else {
                        xl
                    };
                    return Bound {
                        pos_bound: f64::INFINITY,
                        stop_bound: self.offset_shift(y, x, -g),
                        lead: None,
                    };
                }
                if moving_back(ls) {
                    let sp = stop_point_back(
                        Kin { x: xl, ..kin(ls) },
                        self.members[l].d_b,
                        self.members[l].j_b,
                    );
                    Bound {
                        pos_bound: f64::INFINITY,
                        stop_bound: sp - g,
                        lead: None,
                    }
                } else if own_mode == GapControlMode::Fast {
                    fast_dmax = dl;
                    lead_moving = moving_fwd(ls);
                    fast_bound(xl - g, ls.vel, dl, self.members[l].updated, dt)
                } else {
                    Bound {
                        pos_bound: f64::INFINITY,
                        stop_bound: xl - g,
                        lead: None,
                    }
                }
            })
        } else if self.cfg.gap_control_direction == GapControlDirection::Both || establishing {
            self.succ(k).map(|b| {
                let g = self.eff_gap(b);
                let bs = axes[self.members[b].axis].set;
                let xb = s.pos - self.members[b].gap;
                let db = self.members[b].dynamics.max_d;
                let y = self.comp_y(b);
                if y > 0.0 {
                    let x = if moving_fwd(bs) {
                        stop_point(
                            Kin { x: xb, ..kin(bs) },
                            self.members[b].d_b,
                            self.members[b].j_b,
                        )
                    } else {
                        xb
                    };
                    return Bound {
                        pos_bound: f64::INFINITY,
                        stop_bound: -self.offset_shift(y, x, g),
                        lead: None,
                    };
                }
                if moving_fwd(bs) {
                    let sp = stop_point(
                        Kin { x: xb, ..kin(bs) },
                        self.members[b].d_b,
                        self.members[b].j_b,
                    );
                    Bound {
                        pos_bound: f64::INFINITY,
                        stop_bound: -sp - g,
                        lead: None,
                    }
                } else if self.mode_of(b) == GapControlMode::Fast {
                    fast_dmax = db;
                    lead_moving = moving_back(bs);
                    fast_bound(-xb - g, -bs.vel, db, self.members[b].updated, dt)
                } else {
                    Bound {
                        pos_bound: f64::INFINITY,
                        stop_bound: -xb - g,
                        lead: None,
                    }
                }
            })
        } else {
            None
        };
        (c4, fast_dmax, lead_moving)
    }

    /// One planner step of member `k` (§8.5, §8.6).
    pub(super) fn step_member(&mut self, k: usize, dt: f64, axes: &mut [Axis]) {
        let ax = self.members[k].axis;
        // CA owns the set values of its members (drops a single-axis error-reaction job).
        axes[ax].job = None;
        if let Job::Gear { req, gear } = self.members[k].job {
            if self.step_gear(k, req, gear, dt, axes).is_some() {
                return;
            }
        }
        let s = axes[ax].set;
        let job = self.members[k].job;
        let ad = self.members[k].dynamics;
        let own_mode = self.mode_of(k);
        let retreat = self.members[k].retreat;
        let establishing = retreat > ESTABLISH_MIN;
        let sg = frame_sign(s, &job, retreat);
        let cfg = &self.cfg;
        // Command limits (idle: brake with the axis defaults if moving; establishing: retreat
        // by `retreat`, with the group defaults when idle, §1.7).
        let (dy, target) = match job {
            Job::Position { req, target } => (
                Dyn {
                    v: req.dy.v * self.ovr_actual,
                    ..req.dy
                },
                Some(
                    if establishing {
                        s.pos - retreat
                    } else {
                        target
                    } * sg,
                ),
            ),
            Job::Brake { req } => (req.dy, None),
            Job::Gear { req, gear } => (
                Dyn {
                    v: req.dy.v * self.ovr_actual,
                    ..req.dy
                },
                Some(gear.target * sg),
            ),
            Job::Idle if establishing => (
                Dyn {
                    v: cfg.default_velocity * self.ovr_actual,
                    a: cfg.default_acceleration,
                    d: cfg.default_deceleration,
                    j: cfg.default_jerk,
                },
                Some((s.pos - retreat) * sg),
            ),
            Job::Idle => {
                if s.vel == 0.0 && s.acc == 0.0 {
                    self.members[k].ca_limited = false;
                    self.members[k].updated = true;
                    return;
                }
                (
                    Dyn {
                        v: ad.max_v,
                        a: ad.max_a,
                        d: ad.def_d,
                        j: ad.def_j,
                    },
                    None,
                )
            }
        };
        let (c4, fast_dmax, lead_moving) =
            self.c4_bound(k, s, sg, own_mode, establishing, dt, axes);
        // Committed CA braking dynamics (§8.4).
        let m = &mut self.members[k];
        let mut dcmd = dy.d.min(ad.max_d);
        if fast_dmax.is_finite() {
            // Fast (§8.4, §8.6): committed braking min(own, predecessor's maximum); while the
            // predecessor moves the command's deceleration is capped by its maximum too.
            // The braking C4 used in the last cycle stays committed while moving (a softer
            // one could invalidate a state that was safe, §8.4); if it exceeds the
            // predecessor's maximum, C4 is sampled (planner::sampled_excess).
            let (d, j) = (ad.max_d.min(fast_dmax), ad.max_j);
            if s.vel == 0.0 && s.acc == 0.0 {
                (m.d_ca, m.j_ca) = (d, j);
            } else {
                (m.d_ca, m.j_ca) = (d.max(m.d_b), j.max(m.j_b));
            }
            if lead_moving {
                dcmd = dcmd.min(fast_dmax);
            }
        } else if s.vel == 0.0 && s.acc == 0.0 {
            m.d_ca = dcmd;
            m.j_ca = dy.j;
        } else {
            m.d_ca = m.d_ca.max(dcmd);
            m.j_ca = m.j_ca.max(dy.j);
        }
        // DynamicsReferenceSystem: the step is planned on the template's offset path; the
        // motor follows (velocity steps at the curve boundaries are accepted, §5.9).
        let path = job.req().and_then(|r| r.dyn_path);
        let (ks, target, c4) = match path {
            None => (kin(s), target, c4),
            Some(p) => {
                let k = p.slope(s.pos);
                let map = |fx: f64| {
                    if fx.is_finite() {
                        sg * p.to_offset(sg * fx)
                    } else {
                        fx
                    }
                };
                (
                    Kin {
                        x: p.to_offset(s.pos),
                        v: s.vel * k,
                        a: s.acc * k,
                    },
                    target.map(map),
                    c4.map(|b| Bound {
                        pos_bound: map(b.pos_bound),
                        stop_bound: map(b.stop_bound),
                        lead: None,
                    }),
                )
            }
        };
        let fs = if sg > 0.0 { ks } else { ks.mirror() };
        let out = planner::step(&StepIn {
            s: fs,
            vmax: dy.v.min(ad.max_v),
            amax: dy.a.min(ad.max_a),
            dmax: dcmd,
            jmax: dy.j,
            target,
            d_ca: m.d_ca,
            j_ca: m.j_ca,
            c4,
            t: dt,
        });
        let mut e = if sg > 0.0 { out.s } else { out.s.mirror() };
        if let Some(p) = path {
            let x = p.from_offset(e.x);
            let k = p.slope(x);
            e = Kin {
                x,
                v: e.v / k,
                a: e.a / k,
            };
        }
        m.ca_limited = out.ca_limited;
        m.d_b = out.d_b;
        m.j_b = out.j_b;
        m.updated = true;
        let dx = e.x - s.pos;
        axes[ax].set = State1 {
            pos: e.x,
            vel: e.v,
            acc: e.a,
        };
        self.shift(k, dx);
    }
}
