//! Joining and leaving tracks (xplanar.md §5.5): the order of the movers on a track, AdoptTrackOrientation.

use super::*;

impl TrackSystem {
    // ------------------------------------------------------------------ join / leave (§5.5)

    pub(super) fn join_track(
        &mut self,
        objects: &mut dyn MoverDrive,
        i: usize,
        k: usize,
        constraint: DynamicConstraint,
        options: MoveToPositionOptions,
    ) -> Result<PlanarReply, Rejection> {
        let who = format!("mover '{}'", objects.movers()[i].name);
        objects.require_enabled(i, "JoinTrack")?;
        objects.require_mode(i, CommandKind::JoinTrack, "JoinTrack")?;
        let mode = self.require_track_ready(objects, k, &who)?;
        if mode == TrackOperationMode::Moving {
            return Err(reject(
                E_TRACK_MODE_CONFLICT,
                format!(
                    "{who}: JoinTrack while track '{}' is Moving",
                    self.tracks[k].name
                ),
            ));
        }
        let m = &objects.movers()[i];
        let t = &self.tracks[k];
        if t.cs != m.cs {
            return Err(reject(
                E_TARGET_UNREACHABLE,
                format!("{who}: track '{}' is in another coordinate system", t.name),
            ));
        }
        let shift = self.track_shift_at(objects, k, 0);
        let s_j = t.geo.closest(m.xy_out().pos - shift);
        let mut pose = t.geo.pose_at(s_j);
        pose.p += shift;
        let c_end = if options.use_orientation {
            nearest_equivalent(pose.heading_deg(), m.c_out())
        } else {
            m.c_out()
        };
        // Footprint at the join point against movers on or joining the track (§3.2).
        let fp = crate::geometry::ConvexPolygon::rect(pose.p, m.cfg.width, m.cfg.height, c_end);
        for j in 0..objects.movers().len() {
            let o = &objects.movers()[j];
            if j == i {
                continue;
            }
            let there = match (&o.track, o.joining) {
                (Some(tm), _) if tm.track == k => Some(o.footprint()),
                (_, Some((kk, s, _))) if kk == k => Some(crate::geometry::ConvexPolygon::rect(
                    t.geo.pose_at(s).p + shift,
                    o.cfg.width,
                    o.cfg.height,
                    o.c_out(),
                )),
                _ => None,
            };
            if let Some(other_fp) = there {
                if fp.intersects(&other_fp) {
                    return Err(objects.mover_collision(&who, j));
                }
            }
        }
        let refid = if objects.coordinate_system_count() == 1 && objects.parts().is_empty() {
            0
        } else {
            t.cs
        };
        let r = objects.move_to_position(
            self,
            i,
            PositionXYC::with_ref(pose.p.x, pose.p.y, c_end, refid),
            constraint,
            options,
        )?;
        let m = objects.mover_mut(i);
        m.mode = CommandMode::JoiningTrack;
        m.joining = Some((k, s_j, options.use_orientation));
        Ok(r)
    }

    pub(super) fn leave_track(
        &mut self,
        objects: &mut dyn MoverDrive,
        i: usize,
        target: PositionXYC,
        constraint: DynamicConstraint,
        options: MoveToPositionOptions,
    ) -> Result<PlanarReply, Rejection> {
        let who = format!("mover '{}'", objects.movers()[i].name);
        target.check_finite(&who, "target_position")?;
        objects.require_enabled(i, "LeaveTrack")?;
        objects.require_mode(i, CommandKind::LeaveTrack, "LeaveTrack")?;
        let Some(k) = objects.movers()[i].track.as_ref().map(|t| t.track) else {
            return Err(reject(
                E_INVALID_COMMAND_MODE,
                format!("{who}: not on a track"),
            ));
        };
        if self.track_modes(objects)[k] == TrackOperationMode::Moving {
            return Err(reject(
                E_TRACK_MODE_CONFLICT,
                format!(
                    "{who}: LeaveTrack while track '{}' is Moving",
                    self.tracks[k].name
                ),
            ));
        }
        // The track is left at the start of the motion (§5.5): plan as a free move.
        let saved = objects.mover_mut(i).track.take();
        let mode = objects.movers()[i].mode;
        objects.mover_mut(i).mode = CommandMode::FreeMovement;
        match objects.move_to_position(self, i, target, constraint, options) {
            Ok(r) => {
                objects.mover_mut(i).track = saved;
                self.detach_from_track(objects, i);
                let m = objects.mover_mut(i);
                m.mode = CommandMode::LeavingTrack;
                m.leaving = Some(k);
                m.c_mode = CCoordinateMode::Independent;
                Ok(r)
            }
            Err(e) => {
                let m = objects.mover_mut(i);
                m.track = saved;
                m.mode = mode;
                Err(e)
            }
        }
    }

    /// Removes mover `i` from its track (Disable, LeaveTrack).
    pub(crate) fn detach_from_track(&mut self, objects: &mut dyn MoverDrive, i: usize) {
        let m = objects.mover_mut(i);
        m.joining = None;
        if let Some(t) = m.track.take() {
            let order = &mut self.tracks[t.track].order;
            order.retain(|&x| x != i);
            self.renumber(objects, t.track);
        }
    }

    pub(super) fn renumber(&mut self, objects: &mut dyn MoverDrive, k: usize) {
        for (slot, &j) in self.tracks[k].order.iter().enumerate() {
            if let Some(t) = &mut objects.mover_mut(j).track {
                t.slot = slot;
            }
        }
    }

    /// Inserts mover `i` (already carrying its TrackMotion on `k`) into the track order.
    pub(super) fn insert_into_order(&mut self, objects: &mut dyn MoverDrive, i: usize, k: usize) {
        let s_of = |e: &dyn MoverDrive, j: usize| {
            e.movers()[j].track.as_ref().map(|t| t.s()).unwrap_or(0.0)
        };
        let t = &self.tracks[k];
        let s = s_of(objects, i);
        let n = t.order.len();
        let pos = if t.geo.closed() && n > 0 {
            let l = t.length();
            let key = |x: f64| x.rem_euclid(l);
            // Cyclic order: after the mover with the largest key ≤ s (wrapping).
            let mut best: Option<(usize, f64)> = None;
            for (idx, &j) in t.order.iter().enumerate() {
                let d = (key(s) - key(s_of(objects, j))).rem_euclid(l);
                if best.is_none_or(|(_, bd)| d < bd) {
                    best = Some((idx, d));
                }
            }
            best.map(|(idx, _)| idx + 1).unwrap_or(0)
        } else {
            t.order.partition_point(|&j| s_of(objects, j) <= s)
        };
        self.tracks[k].order.insert(pos, i);
        self.renumber(objects, k);
    }

    /// Bookkeeping of the track modes when axes come to rest (called by `finish_idle`).
    pub(crate) fn track_finish_idle(&mut self, objects: &mut dyn MoverDrive, i: usize) {
        let m = &objects.movers()[i];
        let xy_rest = m.path.is_none() && !m.xy.moving();
        if m.mode == CommandMode::JoiningTrack && xy_rest && m.xy_cmd.is_none() {
            let Some((k, s_j, dependent)) = m.joining else {
                objects.mover_mut(i).mode = CommandMode::FreeMovement;
                return;
            };
            let p = self.tracks[k].geo.pose_at(s_j).p + self.track_shift_at(objects, k, 0);
            let m = objects.mover_mut(i);
            m.joining = None;
            if (m.xy.pos - p).norm() <= 1e-6 {
                let mut tm = TrackMotion::new(k, s_j, m.cfg.default_dynamics);
                if dependent {
                    m.c_mode = CCoordinateMode::Dependent;
                    tm.c_off = 0.0;
                } else {
                    m.c_mode = CCoordinateMode::Independent;
                }
                m.track = Some(tm);
                m.mode = CommandMode::OnTrack;
                self.insert_into_order(objects, i, k);
            } else {
                // The approach was stopped (guard): no join.
                m.mode = CommandMode::FreeMovement;
            }
            return;
        }
        if m.mode == CommandMode::LeavingTrack && xy_rest && m.xy_cmd.is_none() {
            let m = objects.mover_mut(i);
            m.leaving = None;
            m.mode = if in_c_window(m.c_out(), m.cfg.c_min, m.cfg.c_max) {
                CommandMode::FreeMovement
            } else {
                CommandMode::CRotationFreeMovement
            };
            return;
        }
        let Some(tm) = &objects.movers()[i].track else {
            return;
        };
        let k = tm.track;
        let s = tm.s();
        let adopt = tm.adopt;
        let m = &objects.movers()[i];
        let c_rest = !m.c.moving() && m.c_cmd.is_none();
        if adopt && c_rest {
            let h = self.tracks[k].geo.pose_at(s).heading_deg();
            let m = objects.mover_mut(i);
            let c = m.c.pos;
            if (c - nearest_equivalent(h, c)).abs() <= 1e-6 {
                m.c_mode = CCoordinateMode::Dependent;
            }
            if let Some(t) = &mut m.track {
                t.adopt = false;
            }
        }
        let m = objects.mover_mut(i);
        if c_rest
            && m.mode == CommandMode::CRotationOnTrack
            && in_c_window(m.c_out(), m.cfg.c_min, m.cfg.c_max)
        {
            m.mode = CommandMode::OnTrack;
        }
    }

    pub(super) fn adopt_track_orientation(
        &mut self,
        objects: &mut dyn MoverDrive,
        i: usize,
        constraint: DynamicConstraint,
        options: crate::track::AdoptTrackOrientationOptions,
    ) -> Result<PlanarReply, Rejection> {
        objects.require_enabled(i, "AdoptTrackOrientation")?;
        objects.require_mode(
            i,
            CommandKind::AdoptTrackOrientation,
            "AdoptTrackOrientation",
        )?;
        let tm = objects.movers()[i].track.as_ref().ok_or_else(|| {
            reject(
                E_INVALID_COMMAND_MODE,
                format!("mover '{}': not on a track", objects.movers()[i].name),
            )
        })?;
        let h = self.tracks[tm.track].geo.pose_at(tm.s()).heading_deg();
        let r = objects.move_c(
            self,
            i,
            h,
            constraint,
            MoveCOptions {
                additional_turns: options.additional_turns,
                direction: options.direction,
            },
        )?;
        if let Some(t) = &mut objects.mover_mut(i).track {
            t.adopt = true;
        }
        Ok(r)
    }
}
