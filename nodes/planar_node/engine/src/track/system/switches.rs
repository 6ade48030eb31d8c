//! Switches (§5.6.4) and the tracks of groups (§5.11): collision ranges, tubes kept free.

use super::*;

impl TrackSystem {
    // ------------------------------------------------------------------ switches (§5.6.4)

    /// Finds the switches (more than two track ends/starts at one point) and the automatic
    /// collision ranges of their tracks: the arc length from the switch after which the
    /// distance to every other track of the switch exceeds 2R.
    pub(super) fn rebuild_switches(&mut self) {
        let mut switches: Vec<crate::track::Switch> = Vec::new();
        for k in 0..self.tracks.len() {
            if self.tracks[k].next.is_empty() {
                continue;
            }
            let mut outgoing = self.tracks[k].next.clone();
            outgoing.sort_unstable();
            let mut incoming: Vec<usize> = outgoing
                .iter()
                .flat_map(|&n| self.tracks[n].prev.iter().copied())
                .collect();
            incoming.sort_unstable();
            incoming.dedup();
            if incoming.len() + outgoing.len() > 2
                && !switches.iter().any(|s| s.outgoing == outgoing)
            {
                switches.push(crate::track::Switch { incoming, outgoing });
            }
        }
        for t in &mut self.tracks {
            t.end_switch = None;
            t.start_switch = None;
            t.range_end = t.params.range_end(0.0);
            t.range_start = t.params.range_start(0.0);
        }
        for (w, sw) in switches.iter().enumerate() {
            // (track, switch at its end?) for every track of the switch.
            let all: Vec<(usize, bool)> = sw
                .incoming
                .iter()
                .map(|&k| (k, true))
                .chain(sw.outgoing.iter().map(|&k| (k, false)))
                .collect();
            let tracks = &self.tracks;
            // Distance from `q` to the part of track `o` within `w` (arc length) of the switch.
            let near = |o: usize, o_end: bool, w: f64, q: V2| -> f64 {
                let g = &tracks[o].geo;
                let l = g.length();
                let mut best = f64::INFINITY;
                let mut x = 0.0;
                while x <= w.min(l) {
                    let p = g.pose_at(if o_end { l - x } else { x }).p;
                    best = best.min((p - q).norm());
                    x += 2.5;
                }
                best
            };
            let range = |me: usize, from_end: bool| -> f64 {
                let g = &tracks[me].geo;
                let l = g.length();
                let mut x = 0.0;
                while x < l {
                    let q = g.pose_at(if from_end { l - x } else { x }).p;
                    let c = tracks[me].params.switch_clearance();
                    let clear = all
                        .iter()
                        .filter(|(o, _)| *o != me)
                        .all(|&(o, o_end)| near(o, o_end, x + c, q) > c);
                    if clear {
                        return x;
                    }
                    x += 5.0;
                }
                l
            };
            let ends: Vec<(usize, f64)> =
                sw.incoming.iter().map(|&k| (k, range(k, true))).collect();
            let starts: Vec<(usize, f64)> =
                sw.outgoing.iter().map(|&k| (k, range(k, false))).collect();
            for (k, r) in ends {
                self.tracks[k].end_switch = Some(w);
                self.tracks[k].range_end = self.tracks[k].params.range_end(r);
            }
            for (k, r) in starts {
                self.tracks[k].start_switch = Some(w);
                self.tracks[k].range_start = self.tracks[k].params.range_start(r);
            }
        }
        self.switches = switches;
    }

    /// True if another mover occupies switch `w` in a way that conflicts with mover `i`
    /// (on an incoming track of `w`, outside its range): a mover reaching into the range of a
    /// track end (unless it is ahead of `i` on the same track and takes the same branch), or a
    /// mover inside the range of a track start that is not `i`'s branch (§5.6.4). No alloc.
    pub(super) fn switch_occupied(&self, objects: &dyn MoverDrive, i: usize, w: usize) -> bool {
        let tm = objects.movers()[i].track.as_ref().expect("on track");
        let my_branch = tm.route.first().copied();
        let sw = &self.switches[w];
        let reach_of = |j: usize| {
            let o = objects.movers()[j].track.as_ref().expect("on track");
            let (lo, hi) = crate::track::gap::stop_interval(o.v, o.a, o.safe.0, o.safe.1);
            (o.s() + lo, o.s() + hi, o.route.first().copied())
        };
        for &k in &sw.incoming {
            let t = &self.tracks[k];
            let zb = t.length() - t.range_end;
            for &j in t.order.iter().rev() {
                if j == i {
                    continue;
                }
                let (_, hi, branch) = reach_of(j);
                if hi < zb - 1e-9 {
                    break;
                }
                if !(k == tm.track && branch == my_branch) {
                    return true;
                }
            }
        }
        for &k in &sw.outgoing {
            if Some(k) == my_branch {
                continue;
            }
            let t = &self.tracks[k];
            for &j in &t.order {
                if j == i {
                    continue;
                }
                let (lo, _, _) = reach_of(j);
                if lo > t.range_start + 1e-9 {
                    break;
                }
                return true;
            }
        }
        false
    }

    // ------------------------------------------------------------------ groups (§5.11)

    /// A command of group member `i` with the swept area `swept` is refused if a Moving
    /// member track of the same group (other than the mover's own) covers any of it.
    pub(crate) fn check_moving_tracks(
        &mut self,
        objects: &mut dyn MoverDrive,
        i: usize,
        swept: &crate::geometry::ConvexPolygon,
    ) -> Result<(), Rejection> {
        let Some(g) = objects.movers()[i].group else {
            return Ok(());
        };
        if !self.tracks.iter().any(|t| t.group == Some(g)) {
            return Ok(());
        }
        let own = objects.movers()[i].track.as_ref().map(|t| t.track);
        let modes = self.track_modes(objects);
        let cs = objects.movers()[i].cs;
        let blocker = self
            .tracks
            .iter()
            .zip(&modes)
            .enumerate()
            .find(|(k, (t, mode))| {
                t.group == Some(g)
                    && Some(*k) != own
                    && **mode == TrackOperationMode::Moving
                    && t.cs == cs
                    && t.tube.iter().any(|q| q.intersects(swept))
            });
        if let Some((_, (t, _))) = blocker {
            let (oid, name) = (t.oid, t.name.clone());
            let who = format!("mover '{}'", objects.movers()[i].name);
            return Err(objects.collision(
                &who,
                PlanarObjectInfo {
                    object_type: PlanarObjectType::Track,
                    id: oid,
                },
                &name,
            ));
        }
        Ok(())
    }

    /// Starting a motion on member tracks that are not Moving yet: their tubes must be free of
    /// the areas of other members of the group (movers on the track excluded, §5.11).
    pub(super) fn check_track_tubes_free(
        &mut self,
        objects: &mut dyn MoverDrive,
        i: usize,
        tracks: &[usize],
    ) -> Result<(), Rejection> {
        let modes = self.track_modes(objects);
        for &k in tracks {
            let Some(g) = self.tracks[k].group else {
                continue;
            };
            if modes[k] == TrackOperationMode::Moving {
                continue;
            }
            let members = objects.groups()[g].movers.clone();
            for j in members {
                let o = &objects.movers()[j];
                if j == i
                    || o.cs != self.tracks[k].cs
                    || o.track.as_ref().is_some_and(|t| tracks.contains(&t.track))
                {
                    continue;
                }
                let area = objects.reservation(j);
                if self.tracks[k].tube.iter().any(|q| q.intersects(&area)) {
                    let who = format!("mover '{}'", objects.movers()[i].name);
                    return Err(objects.mover_collision(&who, j));
                }
            }
        }
        Ok(())
    }
}
