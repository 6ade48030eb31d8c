//! MoveOnTrack (§5.6): routes through linked tracks; positions on parts (§5.12).

use super::*;

impl TrackSystem {
    // ------------------------------------------------------------------ MoveOnTrack (§5.6)

    pub(super) fn move_on_track(
        &mut self,
        objects: &mut dyn MoverDrive,
        i: usize,
        target_track: Option<usize>,
        target: f64,
        constraint: DynamicConstraint,
        options: crate::track::MoveOnTrackOptions,
    ) -> Result<PlanarReply, Rejection> {
        let who = format!("mover '{}'", objects.movers()[i].name);
        finite(&who, "target_position", target)?;
        finite(&who, "options.gap", options.gap)?;
        finite(&who, "options.modulo_tolerance", options.modulo_tolerance)?;
        if options.gap < 0.0 || options.modulo_tolerance < 0.0 {
            return Err(reject(
                E_INVALID_PARAMETER,
                format!(
                    "{who}: gap = {} and modulo_tolerance = {} must not be negative",
                    options.gap, options.modulo_tolerance
                ),
            ));
        }
        objects.require_enabled(i, "MoveOnTrack")?;
        objects.require_mode(i, CommandKind::MoveOnTrack, "MoveOnTrack")?;
        objects.require_group_ready(i)?;
        let dir = options.direction;
        let n = options.additional_turns;
        if n != 0 && matches!(dir, Direction::NonModulo | Direction::ShortestWay) {
            return Err(reject(
                E_INVALID_PARAMETER,
                format!("{who}: additional_turns = {n} not allowed with direction {dir:?}"),
            ));
        }
        if options.modulo_tolerance != 0.0 && dir == Direction::NonModulo {
            return Err(reject(
                E_INVALID_PARAMETER,
                format!("{who}: modulo_tolerance not allowed with NonModulo"),
            ));
        }
        let m = &objects.movers()[i];
        let Some(tm) = m.track.as_ref() else {
            return Err(reject(
                E_INVALID_COMMAND_MODE,
                format!("{who}: not on a track"),
            ));
        };
        let (dyn_, reduced) = m.cfg.xy_dynamics(&constraint, &who)?;
        let cur = tm.track;
        let kt = target_track.unwrap_or(cur);
        let modes = self.track_modes(objects);
        let t = &self.tracks[kt];
        let l = t.length();
        let s = tm.s();
        let (r_target, route) = if kt == cur {
            if t.geo.closed() {
                let r = match dir {
                    Direction::NonModulo => target,
                    _ => modulo_target(target, tm.r, l, options.modulo_tolerance, dir, n).map_err(
                        |_| {
                            reject(
                                E_INVALID_PARAMETER,
                                format!("{who}: additional_turns not allowed with {dir:?}"),
                            )
                        },
                    )?,
                };
                (r, vec![])
            } else {
                if n != 0 {
                    return Err(reject(
                        E_INVALID_PARAMETER,
                        format!("{who}: additional_turns = {n} on an open track"),
                    ));
                }
                let unreachable = !(-1e-9..=l + 1e-9).contains(&target)
                    || dir == Direction::Positive && target < s - 1e-9
                    || dir == Direction::Negative && target > s + 1e-9;
                if unreachable {
                    return Err(reject(
                        E_TARGET_UNREACHABLE,
                        format!(
                            "{who}: target {target} not reachable on track '{}' (length {l}, at {s}, {dir:?})",
                            t.name
                        ),
                    ));
                }
                (tm.base + target.clamp(0.0, l), vec![])
            }
        } else {
            if dir == Direction::Negative {
                return Err(reject(
                    E_TARGET_UNREACHABLE,
                    format!("{who}: cross-track moves go forward only (direction Negative)"),
                ));
            }
            if n != 0 {
                return Err(reject(
                    E_INVALID_PARAMETER,
                    format!("{who}: additional_turns = {n} on a cross-track move"),
                ));
            }
            if !(-1e-9..=l + 1e-9).contains(&target) {
                return Err(reject(
                    E_TARGET_UNREACHABLE,
                    format!(
                        "{who}: target {target} outside track '{}' (length {l})",
                        t.name
                    ),
                ));
            }
            // The target track itself must be ready; the route uses Enabled tracks only.
            if t.sm.state != PlanarState::Enabled {
                return Err(reject(
                    E_TRACK_NOT_READY,
                    format!("{who}: target track '{}' is {:?}", t.name, t.sm.state),
                ));
            }
            let Some(route) = self.route(objects, cur, kt) else {
                return Err(reject(
                    E_TARGET_UNREACHABLE,
                    format!(
                        "{who}: no route from track '{}' to track '{}'",
                        self.tracks[cur].name, t.name
                    ),
                ));
            };
            let mut r = tm.base + self.tracks[cur].length();
            for &k in &route[..route.len() - 1] {
                r += self.tracks[k].length();
            }
            (r + target.clamp(0.0, l), route)
        };
        for &k in std::iter::once(&cur).chain(route.iter()) {
            let t = &self.tracks[k];
            if t.sm.state != PlanarState::Enabled {
                return Err(reject(
                    E_TRACK_NOT_READY,
                    format!("{who}: track '{}' is {:?}", t.name, t.sm.state),
                ));
            }
            if modes[k] == TrackOperationMode::Configuring {
                return Err(reject(
                    E_TRACK_MODE_CONFLICT,
                    format!("{who}: MoveOnTrack while track '{}' is Configuring", t.name),
                ));
            }
        }
        let mut on_route = vec![cur];
        on_route.extend(route.iter().copied());
        self.check_track_tubes_free(objects, i, &on_route)?;
        let tm = objects.movers()[i].track.as_ref().expect("on track");
        let prof = Profile1::to_position(tm.state(), r_target, 0.0, &limits_of(&dyn_))
            .map_err(|e| traj_err(&who, e))?;
        let id = objects.new_id();
        let (m, ev_) = objects.mover_and_events(i);
        end(ev_, &mut m.xy_cmd, CommandState::Aborted);
        end(ev_, &mut m.halt_cmd, CommandState::Aborted);
        let tm = m.track.as_mut().expect("on track");
        tm.plan = Some((prof, 0.0));
        tm.plan_dyn = dyn_;
        tm.cmd_dyn = dyn_;
        tm.gear = None;
        tm.target = TrackTarget::Position(r_target);
        tm.gap = options.gap;
        tm.route = route;
        tm.braking = false;
        tm.limited = false;
        tm.since_replan = 0;
        m.xy_cmd = Some(id);
        m.guard_stop = false;
        started(ev_, m, id, reduced)
    }

    /// Shortest route (by length of the tracks passed) from the end of `from` to `to` over
    /// traversable links between Enabled tracks: the tracks after `from`, ending with `to`
    /// (§5.6.5). The start track is never passed again (that would be a cycle).
    pub(super) fn route(
        &self,
        objects: &dyn MoverDrive,
        from: usize,
        to: usize,
    ) -> Option<Vec<usize>> {
        let n = self.tracks.len();
        let mut dist = vec![f64::INFINITY; n];
        let mut prev = vec![usize::MAX; n];
        let mut done = vec![false; n];
        // A usable link from `u` to `k`: traversable now, to an Enabled track, never back to
        // the start track.
        let usable = |u: usize, k: usize| {
            k != from
                && self.tracks[k].sm.state == PlanarState::Enabled
                && self.traversable(objects, u, k)
        };
        for &k in &self.tracks[from].next {
            if usable(from, k) {
                dist[k] = 0.0;
                prev[k] = from;
            }
        }
        loop {
            let mut u = None;
            for k in 0..n {
                if !done[k] && dist[k].is_finite() && u.is_none_or(|x: usize| dist[k] < dist[x]) {
                    u = Some(k);
                }
            }
            let u = u?;
            if u == to {
                break;
            }
            done[u] = true;
            for &k in &self.tracks[u].next {
                let d = dist[u] + self.tracks[u].length();
                if !done[k] && d < dist[k] && usable(u, k) {
                    dist[k] = d;
                    prev[k] = u;
                }
            }
        }
        let mut r = vec![to];
        let mut k = to;
        while prev[k] != from {
            k = prev[k];
            r.push(k);
        }
        r.reverse();
        Some(r)
    }

    // ------------------------------------------------------------------ part positions (§5.12)

    pub(super) fn track_part(&self, objects: &dyn MoverDrive, k: usize) -> Option<usize> {
        let oid = self.tracks[k].part_oid;
        if oid == 0 {
            return None;
        }
        objects.parts().iter().position(|p| p.oid == oid)
    }

    /// Position index of track `k`'s part for a link (0 = the part's current index).
    pub(super) fn track_part_index(&self, objects: &dyn MoverDrive, k: usize, index: u32) -> u32 {
        match (index, self.track_part(objects, k)) {
            (0, Some(p)) => objects.parts()[p].index,
            (i, _) => i,
        }
    }

    /// Shift of track `k`'s stored geometry with its part at `index` (0 = current) \[mm\].
    pub(crate) fn track_shift_at(&self, objects: &dyn MoverDrive, k: usize, index: u32) -> V2 {
        match self.track_part(objects, k) {
            Some(p) => {
                let part = &objects.parts()[p];
                let i = if index == 0 { part.index } else { index };
                part.positions
                    .get(&i)
                    .map(|q| V2::new(q.x, q.y) - self.tracks[k].geo_origin)
                    .unwrap_or_default()
            }
            None => V2::zeros(),
        }
    }

    /// True if the link `from` end → `to` start is traversable now (§1.6, §5.12): links made
    /// only for specified part positions need exactly those positions; the others need the
    /// two track ends to meet with the parts where they are.
    pub(crate) fn traversable(&self, objects: &dyn MoverDrive, from: usize, to: usize) -> bool {
        if let Some(&(_, fi, ti)) = self.tracks[from].link_only.iter().find(|x| x.0 == to) {
            return self.track_part_index(objects, from, 0) == fi
                && self.track_part_index(objects, to, 0) == ti;
        }
        let (a, b) = (&self.tracks[from], &self.tracks[to]);
        match (a.geo.end_pose(), b.geo.start_pose()) {
            (Some(e), Some(st)) => {
                let pe = e.p + self.track_shift_at(objects, from, 0);
                let ps = st.p + self.track_shift_at(objects, to, 0);
                (pe - ps).norm() <= 1e-3
            }
            _ => false,
        }
    }
}
