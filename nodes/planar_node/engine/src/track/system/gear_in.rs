//! Virtual axes (§5.8.4) and GearInPosOnTrack (§5.8): the coupling law on the master's motion.

use super::*;

impl TrackSystem {
    // ------------------------------------------------------------------ virtual axes (§5.8.4)

    pub(super) fn axis(&self, name: &str) -> Result<usize, Rejection> {
        self.axis_idx
            .get(name)
            .copied()
            .ok_or_else(|| Rejection::unknown_object("axis", name))
    }

    pub(super) fn axis_move(
        &mut self,
        objects: &mut dyn MoverDrive,
        a: usize,
        who: &str,
        plan: impl FnOnce(
            &crate::motion::Axis1,
        ) -> Result<Profile1, motion_core::trajectory::TrajectoryError>,
    ) -> Result<PlanarReply, Rejection> {
        if !self.axes[a].powered {
            return Err(reject(E_INVALID_STATE, format!("{who}: not powered")));
        }
        let p = plan(&self.axes[a].ax).map_err(|e| traj_err(who, e))?;
        let id = objects.new_id();
        let ev_ = objects.events();
        let x = &mut self.axes[a];
        end(ev_, &mut x.cmd, CommandState::Aborted);
        x.ax.start(p);
        x.cmd = Some(id);
        ev(ev_, id, CommandState::Active);
        reply(id, ReplyValue::None)
    }

    /// Advances the virtual axes (before the movers, so slaves see the new master state).
    pub(crate) fn step_axes(&mut self, objects: &mut dyn MoverDrive, dt: f64) {
        for x in &mut self.axes {
            if x.ax.advance(dt) {
                end(objects.events(), &mut x.cmd, CommandState::Done);
            }
        }
    }

    pub(crate) fn axis_snapshots(
        &self,
        old: Vec<crate::snapshot::VirtualAxisSnapshot>,
    ) -> Vec<crate::snapshot::VirtualAxisSnapshot> {
        refill_vec(old, self.axes.len(), |i, old| {
            let x = &self.axes[i];
            crate::snapshot::VirtualAxisSnapshot {
                name: reuse_str(old.name, &x.name),
                oid: x.oid,
                powered: x.powered,
                position: x.ax.pos,
                velocity: x.ax.vel,
                acceleration: x.ax.acc,
                busy: x.cmd.is_some(),
            }
        })
    }

    // ------------------------------------------------------------------ gear-in (§5.8)

    /// The master's motion (master coordinates) as a profile, and the time in it that belongs
    /// to the slave's current state: axes and movers before `i` have already advanced this
    /// cycle, movers after it not yet.
    pub(super) fn master_motion(
        &self,
        objects: &dyn MoverDrive,
        g: &GearIn,
        i: usize,
        dt: f64,
    ) -> Option<(Profile1, f64)> {
        let ((p, t), advanced) = match g.master {
            Master::Mover(j) => {
                let mt = objects.movers()[j].track.as_ref()?;
                let motion = match &mt.plan {
                    Some((mp, t)) => (*mp, *t),
                    None => (Profile1::hold(mt.state()), 0.0),
                };
                (motion, j < i)
            }
            Master::Axis(a) => (self.axes[a].ax.motion(), true),
        };
        let p = if let Master::Mover(_) = g.master {
            p.moved_by(-g.master_origin, 0.0)
        } else {
            p
        };
        if !advanced {
            return Some((p, t));
        }
        Some(if t >= dt {
            (p, t - dt)
        } else {
            // Started this cycle: go back along the start state.
            let s = p.at(t);
            let back = State1 {
                pos: s.pos - s.vel * dt,
                vel: s.vel,
                acc: 0.0,
            };
            (Profile1::hold(back), 0.0)
        })
    }

    /// Route coordinate of the start of track `k` for a mover (None if not on its way).
    pub(super) fn start_r(&self, tm: &TrackMotion, k: usize) -> Option<f64> {
        if k == tm.track {
            return Some(tm.base);
        }
        let mut r = tm.base + self.tracks[tm.track].length();
        for &x in &tm.route {
            if x == k {
                return Some(r);
            }
            r += self.tracks[x].length();
        }
        None
    }

    #[allow(clippy::too_many_arguments)]
    pub(super) fn gear_in(
        &mut self,
        objects: &mut dyn MoverDrive,
        i: usize,
        master: Master,
        trail: Vec<usize>,
        (m_sync, mk): (f64, Option<usize>),
        (s_sync, sk): (f64, usize),
        constraint: DynamicConstraint,
        o: crate::track::GearInPosOnTrackWithMasterMoverOptions,
    ) -> Result<PlanarReply, Rejection> {
        let who = format!("mover '{}'", objects.movers()[i].name);
        finite(&who, "master_sync_position", m_sync)?;
        finite(&who, "slave_sync_position", s_sync)?;
        for (f, v) in [
            ("options.gap", o.gap),
            (
                "options.in_sync_tolerance_distance",
                o.in_sync_tolerance_distance,
            ),
            (
                "options.modulo_tolerance_slave_sync_position",
                o.modulo_tolerance_slave_sync_position,
            ),
            (
                "options.modulo_tolerance_master_sync_position",
                o.modulo_tolerance_master_sync_position,
            ),
        ] {
            if finite(&who, f, v)? < 0.0 {
                return Err(reject(E_INVALID_PARAMETER, format!("{who}: {f} = {v} < 0")));
            }
        }
        objects.require_enabled(i, "GearInPosOnTrackWithMasterMover")?;
        objects.require_mode(i, CommandKind::GearIn, "GearInPosOnTrackWithMasterMover")?;
        let mt = match master {
            Master::Mover(j) => {
                if i == j {
                    return Err(reject(
                        E_INVALID_PARAMETER,
                        format!("{who}: master = slave"),
                    ));
                }
                let mm = &objects.movers()[j];
                if mm.sm.state != PlanarState::Enabled {
                    return Err(reject(
                        E_INVALID_STATE,
                        format!("{who}: master '{}' is {:?}", mm.name, mm.sm.state),
                    ));
                }
                let Some(mt) = mm.track.as_ref() else {
                    return Err(reject(
                        E_INVALID_COMMAND_MODE,
                        format!("{who}: master '{}' is not on a track", mm.name),
                    ));
                };
                Some(mt)
            }
            Master::Axis(_) => None,
        };
        let tm = objects.movers()[i].track.as_ref().expect("OnTrack");
        let cur = tm.track;
        let mut trail = trail;
        if trail.is_empty() {
            trail.push(cur);
            if let (true, Some(mt)) = (o.follow_mover, mt) {
                if mt.track != cur {
                    // The shortest way to the master's track, then the master's path.
                    if let Some(r) = self.route(objects, cur, mt.track) {
                        trail.extend(r);
                    }
                }
                for &k in &mt.route {
                    if !trail.contains(&k) {
                        trail.push(k);
                    }
                }
            }
        }
        let distinct = trail
            .iter()
            .enumerate()
            .all(|(a, x)| !trail[..a].contains(x));
        let contiguous = trail
            .windows(2)
            .all(|w| self.tracks[w[0]].next.contains(&w[1]));
        if trail[0] != cur || !distinct || !contiguous || !trail.contains(&sk) {
            return Err(reject(
                E_TRACKTRAIL_INVALID,
                format!(
                    "{who}: trail {:?} must start with the current track, be contiguous and distinct, and hold the slave sync track",
                    trail.iter().map(|&k| &self.tracks[k].name).collect::<Vec<_>>()
                ),
            ));
        }
        let modes = self.track_modes(objects);
        for &k in &trail {
            if modes[k] == TrackOperationMode::Configuring {
                return Err(reject(
                    E_TRACK_MODE_CONFLICT,
                    format!("{who}: track '{}' is Configuring", self.tracks[k].name),
                ));
            }
        }
        let master_origin = match (mt, mk) {
            (Some(mt), Some(mk)) => match self.start_r(mt, mk) {
                Some(o) => o,
                None => {
                    return Err(reject(
                        E_TARGET_UNREACHABLE,
                        format!(
                            "{who}: the master is not on its way to track '{}'",
                            self.tracks[mk].name
                        ),
                    ))
                }
            },
            _ => 0.0,
        };
        let mut probe = tm.clone();
        probe.route = trail[1..].to_vec();
        let slave_origin = self.start_r(&probe, sk).expect("sync track in the trail");
        let modulo =
            |k: usize, x: f64, now: f64, tol: f64, dir: Direction| -> Result<f64, Rejection> {
                let t = &self.tracks[k];
                if !t.geo.closed() || dir == Direction::NonModulo {
                    return Ok(x);
                }
                modulo_target(x, now, t.length(), tol, dir, 0)
                    .map_err(|_| reject(E_INVALID_PARAMETER, format!("{who}: modulo options")))
            };
        let m_sync = match (mt, mk) {
            (Some(mt), Some(mk)) => modulo(
                mk,
                m_sync,
                mt.r - master_origin,
                o.modulo_tolerance_master_sync_position,
                o.direction_master_sync_position,
            )?,
            _ => m_sync,
        };
        let s_sync = slave_origin
            + modulo(
                sk,
                s_sync,
                tm.r - slave_origin,
                o.modulo_tolerance_slave_sync_position,
                o.direction_slave_sync_position,
            )?;
        let closed = self.tracks[cur].geo.closed();
        let (lo, hi) = if closed {
            (f64::NEG_INFINITY, f64::INFINITY)
        } else {
            let hi = tm.base + trail.iter().map(|&k| self.tracks[k].length()).sum::<f64>();
            (tm.base, hi)
        };
        let m = &objects.movers()[i];
        let (dyn_, reduced) = m.cfg.xy_dynamics(&constraint, &who)?;
        let id = objects.new_id();
        let (m, ev_) = objects.mover_and_events(i);
        end(ev_, &mut m.xy_cmd, CommandState::Aborted);
        end(ev_, &mut m.halt_cmd, CommandState::Aborted);
        let tm = m.track.as_mut().expect("OnTrack");
        tm.target = TrackTarget::None;
        tm.route = trail[1..].to_vec();
        tm.gap = o.gap;
        tm.cmd_dyn = dyn_;
        tm.limited = false;
        tm.gear = Some(GearIn {
            master,
            master_origin,
            m_sync,
            s_sync,
            lo,
            hi,
            dyn_,
            tol: o.in_sync_tolerance_distance.max(1e-3),
            allowed: o.allowed_slave_sync_directions,
            follow: o.follow_mover,
            in_sync: false,
            ever_synced: false,
            coupled: false,
            boundary: false,
        });
        m.xy_cmd = Some(id);
        m.guard_stop = false;
        started(ev_, m, id, reduced)
    }

    /// One cycle of a gear-in: follow the master's path (followMover), compute the target
    /// `s*`, `inSync`, and a fresh time-optimal chase plan to (s* + ṁ·T, ṁ); brake exactly to
    /// the trail boundary when the chase would pass it (§5.8.1).
    pub(super) fn gear_step(&mut self, objects: &mut dyn MoverDrive, i: usize, dt: f64) {
        let Some(tm) = objects.movers()[i].track.as_ref() else {
            return;
        };
        let Some(g) = tm.gear.as_ref() else {
            return;
        };
        if g.boundary || tm.braking {
            return;
        }
        let Some((mp, t0)) = self.master_motion(objects, g, i, dt) else {
            // The master left its track: the coupling ends.
            let (m, ev_) = objects.mover_and_events(i);
            end(ev_, &mut m.xy_cmd, CommandState::Error(E_OBJECT_ERROR));
            let d = m.cfg.default_dynamics;
            if let Some(t) = &mut m.track {
                t.plan_stop(&d);
            }
            return;
        };
        // followMover: the slave's way grows with the master's path.
        let mut extend: Vec<usize> = Vec::new();
        if let (true, Master::Mover(j)) = (g.follow, g.master) {
            let mt = objects.movers()[j]
                .track
                .as_ref()
                .expect("master on a track");
            let mut last = *tm.route.last().unwrap_or(&tm.track);
            for k in std::iter::once(mt.track).chain(mt.route.iter().copied()) {
                if k != tm.track
                    && !tm.route.contains(&k)
                    && !extend.contains(&k)
                    && self.tracks[last].next.contains(&k)
                {
                    extend.push(k);
                    last = k;
                }
            }
        }
        // s* = s_sync + (m - m_sync); `mc` is the master at the slave's current time.
        let off = g.s_sync - g.m_sync;
        let mc = mp.at(t0);
        let s_star = off + mc.pos;
        let in_sync = (tm.r - s_star).abs() <= g.tol && (tm.v - mc.vel).abs() <= 0.1;
        let lim = limits_of(&g.dyn_);
        let state = tm.state();
        // Direct coupling (§5.8.1): once the slave is on the law, it follows the master's
        // own motion as long as that stays within the slave's dynamics.
        let mn = mp.at(t0 + dt);
        let eps = 1e-9;
        let within = mn.vel.abs() <= lim.velocity * (1.0 + eps)
            && mn.acc <= lim.acceleration.max(lim.deceleration) * (1.0 + eps)
            && -mn.acc <= lim.acceleration.max(lim.deceleration) * (1.0 + eps);
        let coupled_plan = (mp.moved_by(off, 0.0), t0);
        let vrel = lim.velocity - mc.vel.abs();
        let (mut p, coupled) = if g.coupled && in_sync && within {
            (Some(coupled_plan), true)
        } else if vrel > 1e-6 {
            // Chase: a time-optimal plan to the target, relative to a frame that moves with
            // the master's current velocity (constant over the horizon, §5.8.1), so that the
            // slave arrives on the law with the master's velocity.
            let rel = State1 {
                pos: tm.r - s_star,
                vel: tm.v - mc.vel,
                acc: tm.a,
            };
            let rl = Limits {
                velocity: vrel,
                ..lim
            };
            match Profile1::to_position(rel, 0.0, 0.0, &rl) {
                Ok(q) if q.duration() <= dt + 1e-12 && within => (Some(coupled_plan), true),
                Ok(q) => (Some((q.moved_by(s_star, mc.vel), 0.0)), false),
                Err(_) => (None, false),
            }
        } else {
            // The master is faster than the slave may go: the slave still tries at its
            // limit, no error (§5.8.1; the master may slow down later).
            let v = mc.vel.clamp(-lim.velocity, lim.velocity);
            (
                Profile1::to_velocity(state, v, &lim).ok().map(|q| (q, 0.0)),
                false,
            )
        };
        let predict = |h: f64| {
            let x = mp.at(t0 + h);
            (x.pos, x.vel)
        };
        let d = (g.dyn_.deceleration, g.dyn_.jerk);
        // allowedSlaveSyncDirections restricts the velocity sign until first synchronous.
        if !g.ever_synced {
            if let Some((q, tq)) = &p {
                let c = q.at(tq + dt);
                let wrong = match g.allowed {
                    SyncDirections::Positive => c.vel < -1e-9,
                    SyncDirections::Negative => c.vel > 1e-9,
                    SyncDirections::Both => false,
                };
                if wrong {
                    p = if tm.v == 0.0 && tm.a == 0.0 {
                        None
                    } else {
                        Profile1::stopping(state, &lim).ok().map(|q| (q, 0.0))
                    };
                }
            }
        }
        // Trail boundary: if the master drives the slave out of its trail (the coupled
        // position where the master comes to rest lies outside), brake at the last moment so
        // that the slave stops exactly on the boundary (error follows); a chase transient that
        // would touch the boundary only holds the slave back.
        let mut boundary = false;
        if let Some((q, tq)) = &p {
            let c = q.at(tq + dt);
            let (lo, hi) = reach(c.pos, c.vel, c.acc, d.0, d.1);
            if hi > g.hi + 1e-9 || lo < g.lo - 1e-9 {
                let (m_end, _) = predict(1e9);
                let s_final = off + m_end;
                let beyond = hi > g.hi + 1e-9;
                if (beyond && s_final > g.hi) || (!beyond && s_final < g.lo) {
                    let edge = if beyond { g.hi } else { g.lo };
                    p = Profile1::to_position(state, edge, 0.0, &lim)
                        .or_else(|_| Profile1::stopping(state, &lim))
                        .ok()
                        .map(|q| (q, 0.0));
                    boundary = true;
                } else {
                    p = if tm.v == 0.0 && tm.a == 0.0 {
                        None
                    } else {
                        Profile1::stopping(state, &lim).ok().map(|q| (q, 0.0))
                    };
                }
            }
        }
        let lens: f64 = extend.iter().map(|&k| self.tracks[k].length()).sum();
        let m = objects.mover_mut(i);
        let tm = m.track.as_mut().expect("on track");
        tm.route.extend(extend);
        tm.plan = p;
        tm.plan_dyn = tm.cmd_dyn;
        let g = tm.gear.as_mut().expect("gear");
        g.hi += lens;
        g.coupled = coupled && !boundary;
        g.in_sync = in_sync;
        g.ever_synced |= in_sync;
        g.boundary = boundary;
    }
}
