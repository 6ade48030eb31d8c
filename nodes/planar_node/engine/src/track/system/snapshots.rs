//! Track and on-track mover snapshots, built in an older snapshot's buffers.

use super::*;

impl TrackSystem {
    // ------------------------------------------------------------------ snapshots

    pub(crate) fn on_track_snapshot(
        &self,
        objects: &dyn MoverDrive,
        m: &Mover,
        old: Option<OnTrackSnapshot>,
    ) -> Option<OnTrackSnapshot> {
        let tm = m.track.as_ref()?;
        let old = old.unwrap_or_default();
        let t = &self.tracks[tm.track];
        let s = tm.s();
        Some(OnTrackSnapshot {
            track: reuse_str(old.track, &t.name),
            track_oid: t.oid,
            set_pos: s,
            set_pos_modulo: if t.geo.closed() {
                let x = s.rem_euclid(t.length());
                if t.length() - x < 1e-9 {
                    0.0
                } else {
                    x
                }
            } else {
                s
            },
            set_velo: tm.v,
            set_acc: tm.a,
            gap: tm.gap,
            waiting: tm.limited || (tm.plan.is_none() && tm.target != TrackTarget::None),
            in_sync: tm.gear.as_ref().is_some_and(|g| g.in_sync),
            gear_master: reuse_opt_str(
                old.gear_master,
                tm.gear.as_ref().map(|g| match g.master {
                    Master::Mover(j) => objects.movers()[j].name.as_str(),
                    Master::Axis(a) => self.axes[a].name.as_str(),
                }),
            ),
        })
    }

    pub(crate) fn track_snapshots(
        &self,
        objects: &dyn MoverDrive,
        old: Vec<TrackSnapshot>,
    ) -> Vec<TrackSnapshot> {
        let modes = self.track_modes(objects);
        let name = |x: &usize| self.tracks[*x].name.as_str();
        refill_vec(old, self.tracks.len(), |k, old| {
            let t = &self.tracks[k];
            TrackSnapshot {
                name: reuse_str(old.name, &t.name),
                oid: t.oid,
                state: t.sm.state,
                operation_mode: modes[k],
                length: t.length(),
                closed_loop: t.geo.closed(),
                mover_count: t.order.len(),
                movers: reuse_strs(
                    old.movers,
                    t.order.iter().map(|&j| objects.movers()[j].name.as_str()),
                ),
                previous_tracks: reuse_strs(old.previous_tracks, t.prev.iter().map(name)),
                subsequent_tracks: reuse_strs(old.subsequent_tracks, t.next.iter().map(name)),
                part_oid: t.part_oid,
                collision_range_start: t.range_start,
                collision_range_end: t.range_end,
                collision_range_mode: t.params.range_mode,
                max_mover_width: t.params.max_mover_width,
                max_mover_height: t.params.max_mover_height,
                check_static_collision: t.params.check_static_collision,
                traversable_subsequent_tracks: reuse_strs(
                    old.traversable_subsequent_tracks,
                    t.next
                        .iter()
                        .filter(|&&x| self.traversable(objects, k, x))
                        .map(name),
                ),
            }
        })
    }
}
