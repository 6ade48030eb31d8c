//! "Check collision against static objects" at TrackAddToGroup (xplanar.md §1.6, §5.11
//! proposal): the track's tube must lie inside the stator area, and must not overlap the tube
//! of another member track of the group except at their connections.
//!
//! Connections: where an end or start of the track meets an end or start of the other track
//! (links and switches), the tubes necessarily overlap. There the pieces within the
//! connection's clearance are exempt on both tracks: the collision range at that end (the arc
//! length after which the tracks are farther apart than the clearance, §5.6.4) and at least one
//! tube width plus one piece, which covers a plain joint without a switch (range 0).

use super::MoverDrive;
use super::Track;
use super::TrackSystem;
use crate::geometry::{ConvexPolygon, V2};
use crate::types::{PlanarObjectInfo, PlanarObjectType};
use motion_core::Rejection;

/// Track end points closer than this meet \[mm\].
const MEET: f64 = 1e-3;

/// Arc-length ranges of a track's tube pieces that are exempt near one connection.
#[derive(Clone, Copy)]
struct Exempt {
    /// Exempt from the start (`false`) or back from the end (`true`).
    at_end: bool,
    /// Arc length from that end \[mm\].
    within: f64,
}

impl TrackSystem {
    /// The §1.6 static check of track `k` against the stator area and the tracks already in
    /// group `g`; Ok when the track's "Check collision against static objects" is FALSE.
    pub(crate) fn track_static_check(
        &mut self,
        objects: &mut dyn MoverDrive,
        k: usize,
        g: usize,
        tube: &[ConvexPolygon],
    ) -> Result<(), Rejection> {
        if !self.tracks[k].params.check_static_collision {
            return Ok(());
        }
        let who = self.track_who(k);
        let cs = self.tracks[k].cs;
        let shift = self.track_shift_at(objects, k, 0);
        let placed: Vec<ConvexPolygon> = tube.iter().map(|q| q.translated(shift)).collect();
        // The stator area of the track's coordinate system (parts at their current positions);
        // an environment without stators is an unbounded plane.
        let tiles = objects.area_tiles(cs);
        if !tiles.is_empty() {
            if let Some(i) = placed.iter().position(|q| !q.inside_tiles(&tiles)) {
                let s = self.tracks[k].length() * i as f64 / placed.len() as f64;
                let (oid, name) = (
                    objects.environment().oid,
                    objects.environment().name.clone(),
                );
                let info = PlanarObjectInfo {
                    object_type: PlanarObjectType::Environment,
                    id: oid,
                };
                let r = objects.collision(&who, info, &name);
                return Err(Rejection {
                    message: format!(
                        "{}: the tube leaves the stator area near s = {s:.1} mm",
                        r.message
                    ),
                    ..r
                });
            }
        }
        for o in 0..self.tracks.len() {
            let t = &self.tracks[o];
            if o == k || t.group != Some(g) || t.cs != cs {
                continue;
            }
            let (mine, theirs) = self.connections(objects, k, o);
            let other: Vec<ConvexPolygon> = {
                let sh = self.track_shift_at(objects, o, 0);
                t.tube.iter().map(|q| q.translated(sh)).collect()
            };
            let (lk, lo) = (self.tracks[k].length(), t.length());
            for (i, a) in placed.iter().enumerate() {
                if exempt(&mine, i, placed.len(), lk) {
                    continue;
                }
                for (j, b) in other.iter().enumerate() {
                    if !exempt(&theirs, j, other.len(), lo) && a.intersects(b) {
                        let (name, oid) = (t.name.clone(), t.oid);
                        let info = PlanarObjectInfo {
                            object_type: PlanarObjectType::Track,
                            id: oid,
                        };
                        return Err(objects.collision(&who, info, &name));
                    }
                }
            }
        }
        Ok(())
    }

    /// The exempt stretches of tracks `k` and `o` at the points where their ends meet.
    fn connections(
        &self,
        objects: &dyn MoverDrive,
        k: usize,
        o: usize,
    ) -> (Vec<Exempt>, Vec<Exempt>) {
        let ends = |t: usize| -> Vec<(bool, V2, f64)> {
            let tr: &Track = &self.tracks[t];
            let sh = self.track_shift_at(objects, t, 0);
            let margin = 2.0 * tr.params.tube_half_width() + 20.0;
            let mut v = Vec::new();
            if let Some(p) = tr.geo.start_pose() {
                v.push((false, p.p + sh, tr.range_start.max(margin)));
            }
            if let Some(p) = tr.geo.end_pose() {
                v.push((true, p.p + sh, tr.range_end.max(margin)));
            }
            v
        };
        let (ek, eo) = (ends(k), ends(o));
        let (mut mine, mut theirs) = (Vec::new(), Vec::new());
        for &(ka, kp, kw) in &ek {
            for &(oa, op, ow) in &eo {
                if (kp - op).norm() <= MEET {
                    mine.push(Exempt {
                        at_end: ka,
                        within: kw,
                    });
                    theirs.push(Exempt {
                        at_end: oa,
                        within: ow,
                    });
                }
            }
        }
        (mine, theirs)
    }
}

/// True if tube piece `i` of `n` (covering an equal share of the length `l`) lies within an
/// exempt stretch.
fn exempt(ex: &[Exempt], i: usize, n: usize, l: f64) -> bool {
    let (a, b) = (l * i as f64 / n as f64, l * (i + 1) as f64 / n as f64);
    ex.iter().any(|e| {
        if e.at_end {
            l - b <= e.within
        } else {
            a <= e.within
        }
    })
}
