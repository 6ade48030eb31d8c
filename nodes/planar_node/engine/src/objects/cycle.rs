//! One cycle of the plane: parts, state machines, every mover's set point with the no-overlap
//! guard, and what happens at a contact outside groups (a crash) or at the stators' edge.

use super::*;

impl Objects {
    // ------------------------------------------------------------------ the cycle

    pub(crate) fn step_parts(&mut self, tracks: &mut dyn TrackHooks, dt: f64) {
        let t = self.timing;
        for p in 0..self.parts.len() {
            let mut done = None;
            if let Some((index, left, id, riders)) = &mut self.parts[p].transit {
                *left -= dt;
                if *left <= 1e-9 {
                    done = Some((*index, *id, std::mem::take(riders)));
                }
            }
            if let Some((index, id, riders)) = done {
                let (_, o_old) = self.parts[p].origin();
                self.parts[p].index = index;
                self.parts[p].transit = None;
                let (cs_new, o_new) = self.parts[p].origin();
                for j in riders {
                    let m = &mut self.movers[j];
                    m.xy.pos += o_new - o_old;
                    m.cs = cs_new;
                    m.envelope = m.footprint();
                }
                // Tracks are fixed to their part and move with it (§1.6), also into the
                // coordinate system of the new position (§1.3, W20 elevator).
                let part_oid = self.parts[p].oid;
                tracks.part_moved(part_oid, cs_new);
                ev(&mut self.pending, id, CommandState::Done);
            }
            let part = &mut self.parts[p];
            if let Some(s) = part.sm.advance(dt, true) {
                let _ = s;
                let mut sink = vec![];
                part.sm.complete(&mut sink);
                self.pending.extend(sink);
            }
        }
        let _ = t;
        self.reconcile_parts();
    }

    pub(crate) fn step_states(&mut self, tracks: &mut dyn TrackHooks, dt: f64) {
        for i in 0..self.movers.len() {
            let at_rest = self.movers[i].at_rest()
                || self.movers[i].sm.reaction == ErrorReaction::Abort
                    && self.movers[i].sm.in_error();
            let state = self.movers[i].sm.state;
            let may = match state {
                PlanarState::Enabling => match self.part_of(&self.movers[i]) {
                    Some(p) => self.parts[p].sm.state == PlanarState::Enabled,
                    None => true,
                },
                PlanarState::Resetting => match self.part_of(&self.movers[i]) {
                    Some(p) => !self.parts[p].sm.in_error(),
                    None => true,
                },
                PlanarState::Disabling | PlanarState::ErrorPending => at_rest,
                _ => true,
            };
            let m = &mut self.movers[i];
            if state == PlanarState::Resetting && !may && m.sm.timer_elapsed() {
                // T13: the mover's part is still in error.
                m.sm.fail_reset(E_PART_DISABLED, &mut self.pending);
                continue;
            }
            if m.sm.advance(dt, may).is_some() {
                m.sm.complete(&mut self.pending);
                match m.sm.state {
                    PlanarState::Enabled => {
                        let win = in_c_window(m.c_out(), m.cfg.c_min, m.cfg.c_max);
                        // After a QuickStop reset a mover is still on its track.
                        m.mode = match (m.track.is_some(), win) {
                            (false, true) => CommandMode::FreeMovement,
                            (false, false) => CommandMode::CRotationFreeMovement,
                            (true, true) => CommandMode::OnTrack,
                            (true, false) => CommandMode::CRotationOnTrack,
                        };
                    }
                    PlanarState::Disabled => {
                        m.mode = CommandMode::Invalid;
                        m.path = None;
                        m.xy = Kin2::at_rest(m.xy.pos);
                        m.c_mode = CCoordinateMode::Independent;
                        // §2.1: a disabled mover is detached from its track.
                        tracks.detach(self, i);
                    }
                    _ => {}
                }
            }
        }
        self.reconcile_parts();
        // Groups have no preconditions.
        for g in &mut self.groups {
            if g.sm.advance(dt, true).is_some() {
                g.sm.complete(&mut self.pending);
            }
        }
    }

    pub(crate) fn step_motion(&mut self, tracks: &mut dyn TrackHooks, dt: f64) {
        let mut grid = std::mem::take(&mut self.grid);
        let mut cand = std::mem::take(&mut self.scratch);
        grid.clear();
        // Fast path (crate::track): every mover on one and the same track, where gap control
        // alone separates them; the guard grid is then not needed this cycle.
        self.guard_full = !self.all_on_one_track();
        if self.guard_full {
            for (i, m) in self.movers.iter().enumerate() {
                grid.insert(m.cs, i as u32, &m.envelope);
            }
        }
        for i in 0..self.movers.len() {
            self.step_mover(tracks, i, dt, &mut grid, &mut cand);
        }
        self.grid = grid;
        self.scratch = cand;
    }

    pub(super) fn esg_check(m: &Mover, sp: &Setpoint, dt: f64) -> Option<(ErrorId, String)> {
        let mx = &m.cfg.max_dynamics;
        let v = V2::new(sp.vel.x, sp.vel.y).norm();
        let a = V2::new(sp.acc.x, sp.acc.y).norm();
        let step = (V2::new(sp.pos.x, sp.pos.y) - m.xy.pos).norm();
        let tol = 1.0 + 1e-6;
        if v > mx.velocity * tol
            || a > mx.acceleration.max(mx.deceleration) * tol
            || step > mx.velocity * dt * tol + 1e-6
        {
            return Some((E_DYNAMICS_VIOLATION, format!("mover '{}': external set point exceeds the maximum dynamics (v {v:.1}, a {a:.1}, step {step:.4})", m.name)));
        }
        None
    }

    pub(super) fn step_mover(
        &mut self,
        tracks: &mut dyn TrackHooks,
        i: usize,
        dt: f64,
        grid: &mut Grid,
        cand: &mut Vec<u32>,
    ) {
        // Aux axes: independent of the footprint.
        {
            let ev_ = &mut self.pending;
            let m = &mut self.movers[i];
            if m.z.advance(dt) {
                end(ev_, &mut m.z_cmd, CommandState::Done);
            }
            if m.a.advance(dt) {
                end(ev_, &mut m.a_cmd, CommandState::Done);
            }
            if m.b.advance(dt) {
                end(ev_, &mut m.b_cmd, CommandState::Done);
            }
        }
        // External set points: consume this cycle's value (or extrapolate).
        let mut esg_abs: Option<Setpoint> = None;
        let mut fault: Option<(ErrorId, String)> = None;
        let timeout = self.esg_timeout_cycles;
        let m = &mut self.movers[i];
        if let Some(e) = &mut m.esg {
            if let Some(f) = e.fault.take() {
                fault = Some(f);
            } else if !e.stopping {
                let sp = match e.pending.take() {
                    Some(sp) => {
                        e.missing = 0;
                        sp
                    }
                    None => {
                        e.missing += 1;
                        let l = e.last;
                        let mut p = l.pos.to_array();
                        let v = l.vel.to_array();
                        let a = l.acc.to_array();
                        let mut nv = v;
                        for k in 0..6 {
                            p[k] += v[k] * dt + a[k] * dt * dt / 2.0;
                            nv[k] += a[k] * dt;
                        }
                        Setpoint {
                            pos: MoverVector::from_array(p),
                            vel: MoverVector::from_array(nv),
                            acc: l.acc,
                        }
                    }
                };
                if e.missing > timeout {
                    fault = Some((
                        E_EXT_SETPOINT_MISSING,
                        format!(
                            "mover '{}': no external set point for {} cycles",
                            m.name, e.missing
                        ),
                    ));
                } else {
                    e.last = sp;
                    if e.mode == ExternalSetpointMode::Absolute {
                        esg_abs = Some(sp);
                    } else {
                        m.offset = sp;
                    }
                }
            }
        }
        if fault.is_none() {
            if let Some(sp) = &esg_abs {
                fault = Self::esg_check(&self.movers[i], sp, dt);
            }
        }
        if let Some((id, _msg)) = fault {
            self.mover_error(i, id, ErrorReaction::QuickStop);
            esg_abs = None;
        }
        if self.movers[i].track.is_some() {
            tracks.step_mover(self, i, dt, grid, cand);
            return;
        }
        let m = &self.movers[i];
        let relative = m
            .esg
            .as_ref()
            .is_some_and(|e| e.mode == ExternalSetpointMode::Relative);
        let moving =
            m.path.is_some() || m.xy.moving() || m.c.moving() || esg_abs.is_some() || relative;
        if !moving {
            self.finish_idle(tracks, i);
            return;
        }
        // Proposal for the next cycle.
        let (xy_next, c_next, path_done) = if let Some(sp) = &esg_abs {
            let xy = Kin2 {
                pos: V2::new(sp.pos.x, sp.pos.y),
                vel: V2::new(sp.vel.x, sp.vel.y),
                acc: V2::new(sp.acc.x, sp.acc.y),
            };
            (
                xy,
                State1 {
                    pos: sp.pos.c,
                    vel: sp.vel.c,
                    acc: sp.acc.c,
                },
                false,
            )
        } else {
            match &m.path {
                Some(p) => {
                    let (st, done) = p.peek(dt);
                    (st.xy, st.c.unwrap_or_else(|| m.c.peek(dt)), done)
                }
                None => (m.xy, m.c.peek(dt), false),
            }
        };
        // Off the stators a mover cannot levitate (see `fall_off`).
        {
            let o = V2::new(m.offset.pos.x, m.offset.pos.y);
            if !self.on_stators(m.cs, xy_next.pos + o) && self.on_stators(m.cs, m.xy.pos + o) {
                self.fall_off(i, xy_next.pos, c_next.pos);
                return;
            }
        }
        let m = &self.movers[i];
        if !m.guard_stop {
            let o = &m.offset;
            let shown = Kin2 {
                pos: xy_next.pos + V2::new(o.pos.x, o.pos.y),
                vel: xy_next.vel + V2::new(o.vel.x, o.vel.y),
                acc: xy_next.acc + V2::new(o.acc.x, o.acc.y),
            };
            let c_shown = State1 {
                pos: c_next.pos + o.pos.c,
                vel: c_next.vel + o.vel.c,
                acc: c_next.acc + o.acc.c,
            };
            let env = m.stop_envelope(&shown, &c_shown);
            grid.query(m.cs, &env, cand);
            if m.group.is_none() {
                // Outside a group the mover has no collision checks (§3.2): it drives on
                // until its footprint touches another mover's, and both crash there.
                let next = ConvexPolygon::rect(shown.pos, m.cfg.width, m.cfg.height, c_shown.pos);
                let hit = cand.iter().map(|&j| j as usize).find(|&j| {
                    j != i
                        && self.movers[j].cs == m.cs
                        && next.intersects(&self.movers[j].footprint())
                });
                if let Some(j) = hit {
                    self.crash(i, j, xy_next.pos, c_next.pos);
                    return;
                }
            }
            let m = &self.movers[i];
            let blocker = cand.iter().map(|&j| j as usize).find(|&j| {
                j != i
                    && self.movers[j].cs == m.cs
                    && m.group.is_some()
                    && env.intersects(&self.movers[j].envelope)
            });
            if let Some(j) = blocker {
                self.guard_fire(i, j, esg_abs.is_some() || relative);
                self.advance_committed(tracks, i, dt);
                return;
            }
            grid.insert(m.cs, i as u32, &env);
            self.movers[i].envelope = env;
        }
        // Commit.
        let ev_ = &mut self.pending;
        let m = &mut self.movers[i];
        if let Some(sp) = esg_abs {
            m.xy = xy_next;
            m.c.pos = c_next.pos;
            m.c.vel = c_next.vel;
            m.c.acc = c_next.acc;
            for (ax, v) in [
                (&mut m.z, (sp.pos.z, sp.vel.z, sp.acc.z)),
                (&mut m.a, (sp.pos.a, sp.vel.a, sp.acc.a)),
                (&mut m.b, (sp.pos.b, sp.vel.b, sp.acc.b)),
            ] {
                ax.pos = v.0;
                ax.vel = v.1;
                ax.acc = v.2;
            }
            if m.esg.as_ref().is_some_and(|e| e.stop_after_pending) {
                let e = m.esg.as_mut().unwrap();
                e.stopping = true;
                e.stop_after_pending = false;
                let (dxy, dc, da) = (
                    m.cfg.max_dynamics,
                    m.cfg.c_max_dynamics,
                    m.cfg.aux_max_dynamics,
                );
                Self::plan_stops(m, &dxy, &dc, &da);
            }
            return;
        }
        let controls_c = m.path.as_ref().is_some_and(|p| p.controls_c);
        if let Some(p) = &mut m.path {
            p.advance(dt);
            m.xy = xy_next;
            if controls_c {
                m.c.pos = c_next.pos;
                m.c.vel = c_next.vel;
                m.c.acc = c_next.acc;
            }
            if path_done {
                m.path = None;
                m.xy = Kin2::at_rest(xy_next.pos);
                end(ev_, &mut m.xy_cmd, CommandState::Done);
            }
        }
        if !controls_c && m.c.advance(dt) {
            end(ev_, &mut m.c_cmd, CommandState::Done);
        }
        self.finish_idle(tracks, i);
    }

    /// Stops mover `i` at the last pose on its way to the next set point (`xy_next`,
    /// `c_next`, internal coordinates) where `blocked` (centre and C as shown) is still false,
    /// found by bisection: a physical stop at a contact, never past it.
    pub(super) fn stop_at_contact(
        &mut self,
        i: usize,
        xy_next: V2,
        c_next: f64,
        blocked: impl Fn(V2, f64) -> bool,
    ) {
        let m = &self.movers[i];
        let (p0, c0) = (m.xy.pos, m.c.pos);
        let (off, c_off) = (V2::new(m.offset.pos.x, m.offset.pos.y), m.offset.pos.c);
        let at = |s: f64| (p0 + (xy_next - p0) * s, c0 + (c_next - c0) * s);
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..40 {
            let mid = (lo + hi) / 2.0;
            let (p, c) = at(mid);
            if blocked(p + off, c + c_off) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        let (p, c) = at(lo);
        let m = &mut self.movers[i];
        m.path = None;
        m.xy = Kin2::at_rest(p);
        m.c.pos = c;
        m.c.freeze();
    }

    /// A crash (proposal, issue 15.2): mover `i`, outside any group, would touch mover `j`
    /// with its next set point. `i` stops at the contact and both go to Error with
    /// E_COLLISION and reaction Abort (set points frozen, power off), each with `objectInfo`
    /// naming the other. Footprints never overlap.
    pub(super) fn crash(&mut self, i: usize, j: usize, xy_next: V2, c_next: f64) {
        let other = self.movers[j].footprint();
        let (w, h) = (self.movers[i].cfg.width, self.movers[i].cfg.height);
        self.stop_at_contact(i, xy_next, c_next, |p, c| {
            ConvexPolygon::rect(p, w, h, c).intersects(&other)
        });
        for (a, b) in [(i, j), (j, i)] {
            let info = PlanarObjectInfo {
                object_type: PlanarObjectType::Mover,
                id: self.movers[b].oid,
            };
            self.movers[a].object_info = info;
            self.mover_error(a, E_COLLISION, ErrorReaction::Abort);
        }
        self.last_object_info = PlanarObjectInfo {
            object_type: PlanarObjectType::Mover,
            id: self.movers[j].oid,
        };
    }

    /// True if `p` (coordinate system `cs`) lies above a stator tile; an area without
    /// stators and parts is unbounded (§1.2). No allocation: runs every cycle.
    pub(super) fn on_stators(&self, cs: u32, p: V2) -> bool {
        if self.parts.is_empty() {
            return self.env.stators.is_empty()
                || crate::geometry::tile_containing(&self.env.stators, p).is_some();
        }
        self.parts.iter().any(|part| {
            let (pcs, o) = part.origin();
            pcs == cs && crate::geometry::tile_containing(&part.tiles, p - o).is_some()
        })
    }

    /// Leaving the stator area (proposal, issue 15.3; §1.2, §6.2): a move's target is not
    /// checked against the area (only a group with the environment checks the boundary, and
    /// "outside the stator area" is not an E_TARGET_UNREACHABLE condition), but a mover
    /// levitates only while its centre is above a stator. Where the centre would leave the
    /// tiles it stops (at the edge) and goes to Error with E_COLLISION, reaction Abort
    /// (levitation off) and `objectInfo` = the environment (304).
    pub(super) fn fall_off(&mut self, i: usize, xy_next: V2, c_next: f64) {
        let cs = self.movers[i].cs;
        let tiles = self.area_tiles(cs);
        let unbounded = self.parts.is_empty() && tiles.is_empty();
        self.stop_at_contact(i, xy_next, c_next, |p, _| {
            !unbounded && crate::geometry::tile_containing(&tiles, p).is_none()
        });
        let info = PlanarObjectInfo {
            object_type: PlanarObjectType::Environment,
            id: self.env.oid,
        };
        self.movers[i].object_info = info;
        self.last_object_info = info;
        self.mover_error(i, E_COLLISION, ErrorReaction::Abort);
    }

    /// The guard refuses the next set point of mover `i` because of mover `j`.
    pub(crate) fn guard_fire(&mut self, i: usize, j: usize, esg: bool) {
        let info = PlanarObjectInfo {
            object_type: PlanarObjectType::Mover,
            id: self.movers[j].oid,
        };
        self.last_object_info = info;
        self.movers[i].object_info = info;
        if esg {
            self.mover_error(i, E_COLLISION, ErrorReaction::QuickStop);
        } else {
            let ev_ = &mut self.pending;
            let m = &mut self.movers[i];
            end(ev_, &mut m.xy_cmd, CommandState::Error(E_COLLISION));
            end(ev_, &mut m.c_cmd, CommandState::Error(E_COLLISION));
            let (dxy, dc, da) = (
                m.cfg.max_dynamics,
                m.cfg.c_max_dynamics,
                m.cfg.aux_max_dynamics,
            );
            let aux = (m.z.clone(), m.a.clone(), m.b.clone());
            Self::plan_stops(m, &dxy, &dc, &da);
            (m.z, m.a, m.b) = aux;
        }
        self.movers[i].guard_stop = true;
    }

    /// Follows the already committed stop (inside the current envelope), no checks needed.
    pub(super) fn advance_committed(&mut self, tracks: &mut dyn TrackHooks, i: usize, dt: f64) {
        let m = &mut self.movers[i];
        if let Some(p) = &mut m.path {
            let (st, done) = p.peek(dt);
            p.advance(dt);
            m.xy = st.xy;
            if done {
                m.path = None;
                m.xy = Kin2::at_rest(st.xy.pos);
            }
        } else if m.esg.is_none() {
            m.xy = Kin2::at_rest(m.xy.pos);
        }
        m.c.advance(dt);
        self.finish_idle(tracks, i);
    }

    /// Bookkeeping once axes come to rest: Halt/Stop done, CRotation exit, reservation release.
    pub(crate) fn finish_idle(&mut self, tracks: &mut dyn TrackHooks, i: usize) {
        tracks.finish_idle(self, i);
        let ev_ = &mut self.pending;
        let m = &mut self.movers[i];
        let xy_rest =
            m.path.is_none() && !m.xy.moving() && m.track.as_ref().is_none_or(|t| t.plan.is_none());
        let c_rest = !m.c.moving();
        if m.guard_stop && xy_rest && c_rest {
            m.guard_stop = false;
        }
        if let Some(e) = &m.esg {
            if e.stopping && xy_rest && c_rest && !m.z.moving() && !m.a.moving() && !m.b.moving() {
                let e = m.esg.take().unwrap();
                ev(ev_, e.session, CommandState::Ended);
                if let Some(s) = e.stop_cmd {
                    ev(ev_, s, CommandState::Done);
                }
                // FreeMovement [manual]; CRotation if the set points left C outside a window.
                m.mode = if in_c_window(m.c_out(), m.cfg.c_min, m.cfg.c_max) {
                    CommandMode::FreeMovement
                } else {
                    CommandMode::CRotationFreeMovement
                };
            }
        }
        if m.halt_cmd.is_some()
            && m.esg.is_none()
            && xy_rest
            && c_rest
            && !m.z.moving()
            && !m.a.moving()
            && !m.b.moving()
        {
            end(ev_, &mut m.halt_cmd, CommandState::Done);
        }
        // §2.2: a rotation-only mode ends when C rests inside a window.
        if c_rest
            && m.c_cmd.is_none()
            && m.mode == CommandMode::CRotationFreeMovement
            && in_c_window(m.c_out(), m.cfg.c_min, m.cfg.c_max)
        {
            m.mode = CommandMode::FreeMovement;
        }
        if xy_rest && c_rest {
            if m.xy_cmd.is_none() && m.c_cmd.is_none() {
                m.reserved = None;
            }
            if !m.guard_stop && m.esg.is_none() {
                m.envelope = m.footprint();
            }
        }
    }

    /// True if every mover is on one and the same track (then the guard is not needed).
    pub(crate) fn all_on_one_track(&self) -> bool {
        let mut k = None;
        for m in &self.movers {
            match (&m.track, k) {
                (None, _) => return false,
                (Some(t), None) => k = Some(t.track),
                (Some(t), Some(x)) if t.track != x => return false,
                _ => {}
            }
        }
        true
    }
}
