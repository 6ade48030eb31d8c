//! The on-track cycle: gap control (§5.6.3), braking, the physical guard.

use super::*;

impl TrackSystem {
    // ------------------------------------------------------------------ the on-track cycle

    /// Forward / backward limits of the reach of mover `i` (route coordinates): the
    /// neighbours' reach intervals minus / plus its gap (§5.6.3). No alloc, no lock.
    pub(super) fn gap_limits(&self, objects: &dyn MoverDrive, i: usize) -> (f64, f64) {
        let tm = objects.movers()[i].track.as_ref().expect("on track");
        let trk = &self.tracks[tm.track];
        let order = &trk.order;
        let n = order.len();
        let l = trk.length();
        let s = tm.s();
        let rel = |j: usize| {
            let o = objects.movers()[j].track.as_ref().expect("on track");
            let (lo, hi) = crate::track::gap::stop_interval(o.v, o.a, o.safe.0, o.safe.1);
            (o.s(), lo, hi)
        };
        let mut fwd = f64::INFINITY;
        let mut bwd = f64::NEG_INFINITY;
        if trk.geo.closed() {
            if n > 1 {
                let f = order[(tm.slot + 1) % n];
                let b = order[(tm.slot + n - 1) % n];
                let (sf, lo_f, _) = rel(f);
                fwd = tm.r + (sf - s).rem_euclid(l) + lo_f - tm.gap;
                let (sb, _, hi_b) = rel(b);
                bwd = tm.r - (s - sb).rem_euclid(l) + hi_b + tm.gap;
            }
            return (fwd, bwd);
        }
        if tm.slot + 1 < n {
            let (sf, lo_f, _) = rel(order[tm.slot + 1]);
            fwd = tm.r + (sf - s) + lo_f - tm.gap;
        } else {
            let mut off = l - s;
            for &k in &tm.route {
                if let Some(&f) = self.tracks[k].order.first() {
                    let (sf, lo_f, _) = rel(f);
                    fwd = tm.r + off + sf + lo_f - tm.gap;
                    break;
                }
                off += self.tracks[k].length();
            }
        }
        // §5.6.4: stop at the border of the collision range while another mover (not on our
        // path) occupies the switch at the end of this track.
        if let Some(w) = trk.end_switch {
            let zb = l - trk.range_end;
            if s < zb - 1e-9 && self.switch_occupied(objects, i, w) {
                fwd = fwd.min(tm.r - s + zb);
            }
        }
        if tm.slot > 0 {
            let (sb, _, hi_b) = rel(order[tm.slot - 1]);
            bwd = tm.r - (s - sb) + hi_b + tm.gap;
        } else {
            for &p in &trk.prev {
                if let Some(&b) = self.tracks[p].order.last() {
                    let (sb, _, hi_b) = rel(b);
                    let lp = self.tracks[p].length();
                    bwd = bwd.max(tm.r - s - (lp - sb) + hi_b + tm.gap);
                }
            }
        }
        (fwd, bwd)
    }

    /// A plan of mover `i` towards its command target clamped by the gap limits, checked for
    /// its first cycle; None if only a committed stop is safe.
    pub(super) fn gap_plan(
        &self,
        objects: &dyn MoverDrive,
        i: usize,
        fwd: f64,
        bwd: f64,
        dt: f64,
    ) -> Option<Profile1> {
        let tm = objects.movers()[i].track.as_ref()?;
        let TrackTarget::Position(x) = tm.target else {
            return None;
        };
        let d = &tm.cmd_dyn;
        let lim = clamp_target(x, tm.r, fwd, bwd);
        let (lo, hi) = reach(tm.r, tm.v, tm.a, d.deceleration, d.jerk);
        if (x >= tm.r && lim < hi) || (x < tm.r && lim > lo) {
            return None;
        }
        let p = Profile1::to_position(tm.state(), lim, 0.0, &limits_of(d)).ok()?;
        let c = p.at(dt.min(p.duration()));
        let old = reach(tm.r, tm.v, tm.a, tm.safe.0, tm.safe.1);
        let new = reach(c.pos, c.vel, c.acc, d.deceleration, d.jerk);
        step_ok(old, new, fwd, bwd).then_some(p)
    }

    pub(super) fn brake_plan(tm: &TrackMotion) -> Option<Profile1> {
        let lim = Limits {
            velocity: tm
                .plan_dyn
                .velocity
                .max(tm.cmd_dyn.velocity)
                .max(tm.v.abs()),
            acceleration: tm.plan_dyn.acceleration.max(tm.safe.0),
            deceleration: tm.safe.0,
            jerk: tm.safe.1,
        };
        Profile1::stopping(tm.state(), &lim).ok()
    }

    /// One cycle of an on-track mover: plan, gap control, route transitions, guard, commit.
    pub(crate) fn step_track_mover(
        &mut self,
        objects: &mut dyn MoverDrive,
        i: usize,
        dt: f64,
        grid: &mut Grid,
        cand: &mut Vec<u32>,
    ) {
        let (active, c_moving) = {
            let m = &objects.movers()[i];
            let tm = m.track.as_ref().expect("on track");
            (tm.active(), m.c.moving())
        };
        if !active && !c_moving {
            objects.finish_idle(self, i);
            return;
        }
        // 0. Gear-in: a fresh chase plan towards the moving target (§5.8.1).
        self.gear_step(objects, i, dt);
        // 1. Plan maintenance: gap checks and re-plans (§5.6.3).
        let needs_limits = {
            let tm = objects.movers()[i].track.as_ref().expect("on track");
            (tm.plan.is_some() && !tm.braking)
                || (matches!(tm.target, TrackTarget::Position(_))
                    && (tm.plan.is_none() || tm.limited))
        };
        if needs_limits {
            let (fwd, bwd) = self.gap_limits(objects, i);
            let mut replace: Option<(Option<Profile1>, bool)> = None;
            {
                let tm = objects.movers()[i].track.as_ref().expect("on track");
                if let Some((p, t)) = &tm.plan {
                    if !tm.braking {
                        let c = p.at((t + dt).min(p.duration()));
                        let old = reach(tm.r, tm.v, tm.a, tm.safe.0, tm.safe.1);
                        let d = &tm.plan_dyn;
                        let new = reach(c.pos, c.vel, c.acc, d.deceleration, d.jerk);
                        if !step_ok(old, new, fwd, bwd) {
                            replace = Some((self.gap_plan(objects, i, fwd, bwd, dt), true));
                        }
                    }
                }
                let tm = objects.movers()[i].track.as_ref().expect("on track");
                if replace.is_none() {
                    if let TrackTarget::Position(x) = tm.target {
                        let lim = clamp_target(x, tm.r, fwd, bwd);
                        let planned_end = tm.plan.as_ref().map(|(p, _)| p.end().pos);
                        let resume = match planned_end {
                            None => {
                                (lim - tm.r).abs() > AT_TARGET
                                    && ((lim - tm.r).abs() > RESUME_MIN || lim == x)
                            }
                            Some(e) => {
                                tm.limited
                                    && tm.since_replan >= REPLAN_CYCLES
                                    && ((lim - e).abs() > REPLAN_MIN || (lim == x && e != x))
                            }
                        };
                        if resume {
                            if let Some(p) = self.gap_plan(objects, i, fwd, bwd, dt) {
                                replace = Some((Some(p), false));
                            }
                        }
                    }
                }
            }
            let m = objects.mover_mut(i);
            let tm = m.track.as_mut().expect("on track");
            tm.since_replan = tm.since_replan.saturating_add(1);
            match replace {
                Some((Some(p), _)) => {
                    let end_pos = p.end().pos;
                    tm.plan = Some((p, 0.0));
                    tm.plan_dyn = tm.cmd_dyn;
                    tm.braking = false;
                    tm.limited = match tm.target {
                        TrackTarget::Position(x) => (end_pos - x).abs() > AT_TARGET,
                        TrackTarget::None => false,
                    };
                    tm.since_replan = 0;
                }
                Some((None, true)) => {
                    if let Some(p) = Self::brake_plan(tm) {
                        tm.plan = Some((p, 0.0));
                        tm.braking = true;
                        tm.limited = true;
                        tm.since_replan = 0;
                    }
                }
                _ => {}
            }
            if let Some(tm) = &mut m.track {
                if tm.plan.is_some() && !tm.braking {
                    tm.safe = (tm.plan_dyn.deceleration, tm.plan_dyn.jerk);
                }
            }
        }
        // 2. Next state along the track.
        let m = &objects.movers()[i];
        let tm = m.track.as_ref().expect("on track");
        let (next, plan_done) = match &tm.plan {
            Some((p, t)) => {
                // A plan that goes on moving after its end (gear-in) never finishes here.
                let endless = p.continues() && p.end().vel != 0.0;
                if !endless && t + dt >= p.duration() - 1e-12 {
                    (p.end(), true)
                } else {
                    (p.at(t + dt), false)
                }
            }
            None => (tm.state(), false),
        };
        let (next, plan_done) = if plan_done {
            (
                State1 {
                    pos: next.pos,
                    vel: 0.0,
                    acc: 0.0,
                },
                true,
            )
        } else {
            (next, false)
        };
        // Route transition (§5.6.5): s passes the end of the current track.
        let mut k = tm.track;
        let mut base = tm.base;
        let mut switch_to: Option<usize> = None;
        if !tm.route.is_empty() && next.pos - base >= self.tracks[k].length() - 1e-12 {
            base += self.tracks[k].length();
            k = tm.route[0];
            switch_to = Some(k);
        }
        let geo = &self.tracks[k].geo;
        let mut pose: TrackPose = geo.pose_at(next.pos - base);
        if self.tracks[k].part_oid != 0 {
            // Tracks move with their part (§1.6).
            pose.p += self.track_shift_at(objects, k, 0);
        }
        let tng = pose.tangent();
        let nrm = V2::new(-tng.y, tng.x);
        let xy_next = Kin2 {
            pos: pose.p,
            vel: tng * next.vel,
            acc: tng * next.acc + nrm * (pose.kappa * next.vel * next.vel),
        };
        let dependent = m.c_mode == CCoordinateMode::Dependent;
        let c_next = if dependent {
            let c = nearest_equivalent(pose.heading_deg(), m.c.pos);
            State1 {
                pos: c,
                vel: (pose.kappa * next.vel).to_degrees(),
                acc: (pose.kappa * next.acc).to_degrees(),
            }
        } else {
            m.c.peek(dt)
        };
        // 3. The no-overlap guard against everything that is not gap-controlled with us.
        if !objects.guard_full() {
            // All movers are on this one track: gap control separates them; keep a cheap,
            // conservative envelope (square of the diagonal grown by the maximum-dynamics stop
            // distance) for the cycle in which a mover leaves the track.
            let (lo, hi) = crate::motion::stop_range(
                next.vel,
                next.acc,
                m.cfg.max_dynamics.deceleration,
                m.cfg.max_dynamics.jerk,
            );
            let h = m.diag() / 2.0 + lo.abs().max(hi.abs());
            let c = xy_next.pos;
            let env =
                crate::geometry::ConvexPolygon::aabb_box(c - V2::new(h, h), c + V2::new(h, h));
            objects.mover_mut(i).envelope = env;
        } else if !m.guard_stop {
            let o = &m.offset;
            let shown = Kin2 {
                pos: xy_next.pos + V2::new(o.pos.x, o.pos.y),
                vel: xy_next.vel,
                acc: xy_next.acc,
            };
            let env = m.stop_envelope(&shown, &c_next);
            grid.query(m.cs, &env, cand);
            let my_track = k;
            let blocker = cand.iter().map(|&j| j as usize).find(|&j| {
                if j == i || objects.movers()[j].cs != m.cs {
                    return false;
                }
                if let Some(o) = &objects.movers()[j].track {
                    let t = &self.tracks[my_track];
                    if o.track == my_track || t.next.contains(&o.track) || t.prev.contains(&o.track)
                    {
                        return false;
                    }
                }
                env.intersects(&objects.movers()[j].envelope)
            });
            if let Some(j) = blocker {
                self.track_guard_fire(objects, i, j);
                objects.finish_idle(self, i);
                return;
            }
            grid.insert(m.cs, i as u32, &env);
            objects.mover_mut(i).envelope = env;
        }
        // 4. Commit.
        let (m, ev_) = objects.mover_and_events(i);
        let tm = m.track.as_mut().expect("on track");
        tm.r = next.pos;
        tm.v = next.vel;
        tm.a = next.acc;
        if let Some((_, t)) = &mut tm.plan {
            *t += dt;
        }
        let old_track = tm.track;
        if let Some(nk) = switch_to {
            tm.track = nk;
            tm.base = base;
            tm.route.remove(0);
        }
        if plan_done {
            tm.plan = None;
            tm.braking = false;
            if tm.gear.as_ref().is_some_and(|g| g.boundary) {
                // §5.8.1: stopped exactly at the trail boundary; the coupling ends in error.
                tm.gear = None;
                end(
                    ev_,
                    &mut m.xy_cmd,
                    CommandState::Error(E_TRACK_BOUNDARY_REACHED),
                );
            }
            let tm = m.track.as_mut().expect("on track");
            if let TrackTarget::Position(x) = tm.target {
                if (tm.r - x).abs() <= AT_TARGET {
                    tm.r = x;
                    tm.target = TrackTarget::None;
                    tm.limited = false;
                    tm.route.clear();
                    end(ev_, &mut m.xy_cmd, CommandState::Done);
                }
            }
        }
        m.xy = xy_next;
        if dependent {
            m.c.pos = c_next.pos;
            m.c.vel = c_next.vel;
            m.c.acc = c_next.acc;
        } else if m.c.advance(dt) {
            end(ev_, &mut m.c_cmd, CommandState::Done);
        }
        if let Some(nk) = switch_to {
            self.tracks[old_track].order.retain(|&x| x != i);
            self.renumber(objects, old_track);
            self.insert_into_order(objects, i, nk);
        }
        objects.finish_idle(self, i);
    }

    /// The guard refuses the next set point of on-track mover `i` because of mover `j`:
    /// the command fails with E_COLLISION and the mover stops along the track (max dynamics).
    pub(super) fn track_guard_fire(&mut self, objects: &mut dyn MoverDrive, i: usize, j: usize) {
        let id = objects.movers()[j].oid;
        objects.set_blocking_object(PlanarObjectInfo {
            object_type: PlanarObjectType::Mover,
            id,
        });
        let (m, ev_) = objects.mover_and_events(i);
        end(ev_, &mut m.xy_cmd, CommandState::Error(E_COLLISION));
        let mx = m.cfg.max_dynamics;
        if let Some(tm) = &mut m.track {
            tm.plan_stop(&mx);
            tm.safe = (mx.deceleration, mx.jerk);
            tm.braking = true;
        }
        m.guard_stop = true;
    }
}
