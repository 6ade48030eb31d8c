//! The environment (§3.1) and part (§3.5, §2.6) commands.

use super::*;

impl Objects {
    // ------------------------------------------------------------------ environment (§3.1)

    pub(super) fn env_add_stator(&mut self, x: f64, y: f64) -> Result<PlanarReply, Rejection> {
        let who = format!("environment '{}'", self.env.name);
        finite(&who, "lower_x", x)?;
        finite(&who, "lower_y", y)?;
        if self.env.processing_unit_oid > 0 || !self.parts.is_empty() {
            return Err(reject(
                E_INVALID_STATE,
                format!("{who}: stators come from the processing unit configuration"),
            ));
        }
        let t = V2::new(x, y);
        if let Some(o) = self.env.stators.iter().find(|s| tiles_overlap(**s, t)) {
            return Err(reject(
                E_INVALID_PARAMETER,
                format!(
                    "{who}: stator ({x}, {y}) overlaps stator ({}, {})",
                    o.x, o.y
                ),
            ));
        }
        self.env.stators.push(t);
        self.done_now()
    }

    pub(super) fn env_tiles_for_boundary(&self) -> Vec<V2> {
        if self.parts.is_empty() {
            self.env.stators.clone()
        } else {
            // Processing unit: all parts at their current positions (per CS; counted together).
            let mut t = vec![];
            for cs in &self.coordinate_systems {
                t.extend(self.area_tiles(*cs));
            }
            t
        }
    }

    pub(crate) fn done_now(&mut self) -> Result<PlanarReply, Rejection> {
        let id = self.new_id();
        ev(&mut self.pending, id, CommandState::Done);
        Ok(PlanarReply {
            id,
            warning_id: ErrorId::NONE,
            value: ReplyValue::None,
        })
    }

    // ------------------------------------------------------------------ parts (§3.5, §2.6)

    pub(super) fn part_initialized(&self, p: usize) -> Result<(), Rejection> {
        if !self.parts[p].initialized {
            return Err(reject(
                E_PART_NOT_INITIALIZED,
                format!("part '{}': Initialize first", self.parts[p].name),
            ));
        }
        Ok(())
    }

    pub(super) fn activate_position(
        &mut self,
        p: usize,
        index: u32,
    ) -> Result<PlanarReply, Rejection> {
        self.part_initialized(p)?;
        let part = &self.parts[p];
        let who = format!("part '{}'", part.name);
        if !part.positions.contains_key(&index) || index == 0 {
            return Err(reject(
                E_INVALID_POSITION_INDEX,
                format!("{who}: position_index = {index} does not exist"),
            ));
        }
        if part.transit.is_some() {
            return Err(reject(
                E_INVALID_STATE,
                format!("{who}: ActivatePosition already running"),
            ));
        }
        let (cs_old, o_old) = part.origin();
        let riders: Vec<usize> = (0..self.movers.len())
            .filter(|&j| part.contains(self.movers[j].cs, self.movers[j].xy_out().pos))
            .collect();
        let (cs_new, tiles_new) = part.world_tiles_at(index);
        let (_, tiles_old) = part.world_tiles_at(part.index);
        for &j in &riders {
            let m = &self.movers[j];
            if !m.at_rest() {
                return Err(reject(
                    E_INVALID_STATE,
                    format!("{who}: mover '{}' on the part is moving", m.name),
                ));
            }
            if !m.footprint().inside_tiles(&tiles_old) {
                return Err(reject(
                    E_INVALID_STATE,
                    format!("{who}: mover '{}' straddles the part border", m.name),
                ));
            }
        }
        for (k, q) in self.parts.iter().enumerate() {
            if k == p {
                continue;
            }
            let (qcs, qt) = q.world_tiles_at(q.index);
            if qcs == cs_new
                && qt
                    .iter()
                    .any(|a| tiles_new.iter().any(|b| tiles_overlap(*a, *b)))
            {
                return Err(reject(
                    E_INVALID_STATE,
                    format!("{who}: position {index} overlaps part '{}'", q.name),
                ));
            }
        }
        let o_new = V2::new(part.positions[&index].x, part.positions[&index].y);
        for &j in &riders {
            let m = &self.movers[j];
            let fp = ConvexPolygon::rect(
                m.xy_out().pos - o_old + o_new,
                m.cfg.width,
                m.cfg.height,
                m.c_out(),
            );
            for (k, o) in self.movers.iter().enumerate() {
                if !riders.contains(&k) && o.cs == cs_new && fp.intersects(&o.envelope) {
                    return Err(self.mover_collision(&who, k));
                }
            }
        }
        let _ = cs_old;
        let id = self.new_id();
        self.parts[p].transit = Some((index, self.part_move_time, id, riders));
        ev(&mut self.pending, id, CommandState::Active);
        Ok(PlanarReply {
            id,
            warning_id: ErrorId::NONE,
            value: ReplyValue::None,
        })
    }

    /// Does mover `m` keep the parts of its CS enabled (§2.6)?
    pub(super) fn holds_parts(m: &Mover) -> bool {
        match m.sm.state {
            PlanarState::Enabling | PlanarState::Enabled | PlanarState::Disabling => true,
            PlanarState::ErrorPending | PlanarState::Error | PlanarState::Resetting => {
                m.sm.reaction == ErrorReaction::QuickStop
            }
            _ => false,
        }
    }

    /// A part is enabled iff its CS holds an enabled mover and it is not force-disabled (§2.6).
    pub(super) fn reconcile_parts(&mut self) {
        if self.parts.is_empty() {
            return;
        }
        let mut held: Vec<u32> = vec![];
        for m in &self.movers {
            if Self::holds_parts(m) && !held.contains(&m.cs) {
                held.push(m.cs);
            }
        }
        let t = self.timing;
        for p in &mut self.parts {
            if p.sm.in_error() {
                continue;
            }
            let want = !p.force_disabled && held.contains(&p.origin().0);
            p.sm.drive(want, &t);
        }
    }

    pub(super) fn mover_error(&mut self, i: usize, id: ErrorId, reaction: ErrorReaction) {
        let t = self.timing;
        let ev_ = &mut self.pending;
        let m = &mut self.movers[i];
        if !m.sm.error(id, reaction, &t, ev_) && m.sm.state != PlanarState::ErrorPending {
            return;
        }
        for slot in [
            &mut m.xy_cmd,
            &mut m.c_cmd,
            &mut m.z_cmd,
            &mut m.a_cmd,
            &mut m.b_cmd,
            &mut m.halt_cmd,
        ] {
            end(ev_, slot, CommandState::Error(id));
        }
        if let Some(e) = m.esg.take() {
            ev(ev_, e.session, CommandState::Error(id));
            if let Some(s) = e.stop_cmd {
                ev(ev_, s, CommandState::Error(id));
            }
            m.offset.vel = MoverVector::default();
            m.offset.acc = MoverVector::default();
        }
        if m.sm.reaction == ErrorReaction::Abort {
            // Set points frozen, power off, z drops.
            m.path = None;
            m.xy = Kin2::at_rest(m.xy.pos);
            if let Some(t) = &mut m.track {
                t.freeze();
            }
            for ax in [&mut m.c, &mut m.a, &mut m.b] {
                ax.freeze();
            }
            m.z = Axis1::at(m.cfg.z_range[0].max(0.0).min(m.cfg.z_range[1]));
            m.guard_stop = false;
            m.envelope = m.footprint();
        } else {
            let (dxy, dc, da) = (
                m.cfg.max_dynamics,
                m.cfg.c_max_dynamics,
                m.cfg.aux_max_dynamics,
            );
            Self::plan_stops(m, &dxy, &dc, &da);
        }
    }
}
