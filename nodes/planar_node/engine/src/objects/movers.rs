//! The mover commands (xplanar.md §3.2): MoveToPosition, MoveC, the aux axes, Halt, Enable,
//! Disable, Reset, SetPosition, external set points, groups and part positions.

use super::*;

impl Objects {
    // ------------------------------------------------------------------ mover commands (§3.2)

    pub(crate) fn move_to_position(
        &mut self,
        tracks: &mut dyn TrackHooks,
        i: usize,
        target: PositionXYC,
        constraint: DynamicConstraint,
        options: MoveToPositionOptions,
    ) -> Result<PlanarReply, Rejection> {
        let who = format!("mover '{}'", self.movers[i].name);
        target.check_finite(&who, "target_position")?;
        self.require_enabled(i, "MoveToPosition")?;
        self.require_mode(i, CommandKind::MoveToPosition, "MoveToPosition")?;
        self.require_group_ready(i)?;
        self.require_part_still(i)?;
        let (cs, p) = self.resolve(&who, target.x, target.y, target.reference_id)?;
        let m = &self.movers[i];
        if cs != m.cs {
            return Err(reject(
                E_TARGET_UNREACHABLE,
                format!(
                    "{who}: target is in coordinate system 0x{cs:08X}, the mover is in 0x{:08X}",
                    m.cs
                ),
            ));
        }
        let (dxy, red1) = m.cfg.xy_dynamics(&constraint, &who)?;
        let (dc, _) = m.cfg.c_dynamics(&DynamicConstraint::default(), &who)?;
        // Plan on internal coordinates: subtract relative offsets.
        let off = V2::new(m.offset.pos.x, m.offset.pos.y);
        let c_target = target.c - m.offset.pos.c;
        let c_arg = options
            .use_orientation
            .then_some((m.c.state(), c_target, &dc));
        let plan = PathPlan::to_point(m.xy, p - off, &dxy, c_arg).map_err(|e| traj_err(&who, e))?;
        let c_end = if options.use_orientation {
            target.c
        } else {
            m.c_out()
        };
        let rotates = options.use_orientation && (c_end - m.c_out()).abs() > 1e-12 || m.c.moving();
        let end_fp = if rotates {
            m.square_at(p)
        } else {
            ConvexPolygon::rect(p, m.cfg.width, m.cfg.height, c_end)
        };
        let start = if rotates {
            ConvexPolygon::hull_of(&m.envelope, &m.square_at(m.xy_out().pos))
        } else {
            m.envelope
        };
        let swept = ConvexPolygon::hull_of(&start, &end_fp);
        self.check_swept(tracks, i, &swept)?;
        let id = self.new_id();
        let ev_ = &mut self.pending;
        let m = &mut self.movers[i];
        end(ev_, &mut m.xy_cmd, CommandState::Aborted);
        end(ev_, &mut m.halt_cmd, CommandState::Aborted);
        if options.use_orientation {
            end(ev_, &mut m.c_cmd, CommandState::Aborted);
            m.c.drop_plan();
        }
        m.path = Some(plan);
        m.guard_stop = false;
        m.xy_cmd = Some(id);
        m.reserved = Some(match m.reserved {
            Some(r) => ConvexPolygon::hull_of(&r, &swept),
            None => swept,
        });
        started(ev_, m, id, red1)
    }

    pub(crate) fn move_c(
        &mut self,
        tracks: &mut dyn TrackHooks,
        i: usize,
        target: f64,
        constraint: DynamicConstraint,
        options: MoveCOptions,
    ) -> Result<PlanarReply, Rejection> {
        let who = format!("mover '{}'", self.movers[i].name);
        finite(&who, "target_position", target)?;
        self.require_enabled(i, "MoveC")?;
        self.require_mode(i, CommandKind::MoveC, "MoveC")?;
        self.require_group_ready(i)?;
        let m = &self.movers[i];
        if m.path.as_ref().is_some_and(|p| p.controls_c) {
            return Err(reject(
                E_AXIS_BUSY,
                format!("{who}: C is controlled by the active XY command"),
            ));
        }
        let now = m.c.pos;
        let abs = modulo_target(
            target - m.offset.pos.c,
            now,
            m.cfg.c_modulus,
            m.cfg.c_modulo_tolerance,
            options.direction,
            options.additional_turns,
        )
        .map_err(|_| {
            reject(
                E_INVALID_PARAMETER,
                format!(
                    "{who}: additional_turns = {} not allowed with direction {:?}",
                    options.additional_turns, options.direction
                ),
            )
        })?;
        let (cmin, cmax) = (m.cfg.c_min, m.cfg.c_max);
        let leaves_window = !range_in_one_window(now, abs, cmin, cmax);
        if leaves_window && !m.xy_standing() {
            return Err(reject(
                E_AXIS_BUSY,
                format!("{who}: a MoveC leaving the C windows needs XY at rest"),
            ));
        }
        let (dc, red) = m.cfg.c_dynamics(&constraint, &who)?;
        let prof = m.c.plan_to(abs, &dc).map_err(|e| traj_err(&who, e))?;
        if (abs - now).abs() > 1e-12 || m.c.moving() {
            let end_p = m
                .path
                .as_ref()
                .map(|p| p.peek(f64::INFINITY).0.xy.pos)
                .unwrap_or(m.xy.pos)
                + V2::new(m.offset.pos.x, m.offset.pos.y);
            let swept = ConvexPolygon::hull_of(
                &ConvexPolygon::hull_of(&m.envelope, &m.square_at(m.xy_out().pos)),
                &m.square_at(end_p),
            );
            self.check_swept(tracks, i, &swept)?;
            let m = &mut self.movers[i];
            m.reserved = Some(match m.reserved {
                Some(r) => ConvexPolygon::hull_of(&r, &swept),
                None => swept,
            });
        }
        let id = self.new_id();
        let ev_ = &mut self.pending;
        let m = &mut self.movers[i];
        end(ev_, &mut m.c_cmd, CommandState::Aborted);
        m.c.start(prof);
        m.c_cmd = Some(id);
        m.c_mode = CCoordinateMode::Independent;
        if let Some(t) = &mut m.track {
            t.adopt = false;
        }
        if leaves_window {
            m.mode = match m.mode {
                CommandMode::OnTrack | CommandMode::CRotationOnTrack => {
                    CommandMode::CRotationOnTrack
                }
                _ => CommandMode::CRotationFreeMovement,
            };
        }
        started(ev_, m, id, red)
    }

    pub(super) fn move_aux(
        &mut self,
        i: usize,
        axis: usize,
        target: f64,
        constraint: DynamicConstraint,
    ) -> Result<PlanarReply, Rejection> {
        let names = ["MoveZ", "MoveA", "MoveB"];
        let who = format!("mover '{}'", self.movers[i].name);
        finite(&who, "target_position", target)?;
        self.require_enabled(i, names[axis])?;
        self.require_mode(i, CommandKind::MoveZab, names[axis])?;
        let m = &self.movers[i];
        let range = [m.cfg.z_range, m.cfg.a_range, m.cfg.b_range][axis];
        if target < range[0] - 1e-9 || target > range[1] + 1e-9 {
            return Err(reject(
                E_INVALID_PARAMETER,
                format!(
                    "{who}: {} target_position = {target} outside [{}, {}]",
                    names[axis], range[0], range[1]
                ),
            ));
        }
        let (d, red) = m.cfg.aux_dynamics(&constraint, &who)?;
        let ax = [&m.z, &m.a, &m.b][axis];
        let prof = ax.plan_to(target, &d).map_err(|e| traj_err(&who, e))?;
        let id = self.new_id();
        let ev_ = &mut self.pending;
        let m = &mut self.movers[i];
        let (ax, slot) = match axis {
            0 => (&mut m.z, &mut m.z_cmd),
            1 => (&mut m.a, &mut m.a_cmd),
            _ => (&mut m.b, &mut m.b_cmd),
        };
        end(ev_, slot, CommandState::Aborted);
        ax.start(prof);
        *slot = Some(id);
        started(ev_, m, id, red)
    }

    /// Plans stops on every moving axis with `dxy`/`dc`/`daux` (Halt, Disable, QuickStop).
    pub(crate) fn plan_stops(m: &mut Mover, dxy: &Dynamics, dc: &Dynamics, daux: &Dynamics) {
        if let Some(t) = &mut m.track {
            // On a track the stop happens along the track (§3.2 Halt).
            t.plan_stop(dxy);
        } else if m.path.is_some() || m.xy.moving() {
            m.path = PathPlan::stop(m.xy, dxy).ok();
        }
        // A dependent C rides on the track motion (§5.9): it stops with it.
        let c_rides = m.track.is_some() && m.c_mode == CCoordinateMode::Dependent;
        if m.c.moving() && !c_rides {
            if let Ok(p) = m.c.plan_stop(dc) {
                m.c.start(p);
            }
        }
        for ax in [&mut m.z, &mut m.a, &mut m.b] {
            if ax.moving() {
                if let Ok(p) = ax.plan_stop(daux) {
                    ax.start(p);
                }
            }
        }
    }

    pub(crate) fn halt(
        &mut self,
        i: usize,
        constraint: DynamicConstraint,
    ) -> Result<PlanarReply, Rejection> {
        let who = format!("mover '{}'", self.movers[i].name);
        self.require_enabled(i, "Halt")?;
        self.require_mode(i, CommandKind::Halt, "Halt")?;
        let m = &self.movers[i];
        let (dxy, _) = m.cfg.xy_dynamics(&constraint, &who)?;
        let (dc, _) = m.cfg.c_dynamics(&DynamicConstraint::default(), &who)?;
        let (da, _) = m.cfg.aux_dynamics(&DynamicConstraint::default(), &who)?;
        let id = self.new_id();
        let ev_ = &mut self.pending;
        let m = &mut self.movers[i];
        for slot in [
            &mut m.xy_cmd,
            &mut m.c_cmd,
            &mut m.z_cmd,
            &mut m.a_cmd,
            &mut m.b_cmd,
            &mut m.halt_cmd,
        ] {
            end(ev_, slot, CommandState::Aborted);
        }
        if let Some(e) = &mut m.esg {
            if e.mode == ExternalSetpointMode::Absolute {
                e.stopping = true;
                e.pending = None;
            } else {
                // Relative: offsets frozen, session over.
                m.offset.vel = MoverVector::default();
                m.offset.acc = MoverVector::default();
                let e = m.esg.take().unwrap();
                ev(ev_, e.session, CommandState::Ended);
            }
        }
        Self::plan_stops(m, &dxy, &dc, &da);
        m.halt_cmd = Some(id);
        ev(ev_, id, CommandState::Active);
        Ok(PlanarReply {
            id,
            warning_id: ErrorId::NONE,
            value: ReplyValue::None,
        })
    }

    pub(super) fn enable_mover(&mut self, i: usize) -> Result<PlanarReply, Rejection> {
        let who = format!("mover '{}'", self.movers[i].name);
        if let Some(p) = self.part_of(&self.movers[i]) {
            if self.parts[p].force_disabled {
                return Err(reject(
                    E_PART_DISABLED,
                    format!("{who}: part '{}' is force-disabled", self.parts[p].name),
                ));
            }
        }
        let id = self.new_id();
        let t = self.timing;
        let r = self.movers[i].sm.enable(id, &t, &who, &mut self.pending)?;
        if r == Accepted::AlreadyThere {
            ev(&mut self.pending, id, CommandState::Done);
        } else {
            ev(&mut self.pending, id, CommandState::Active);
        }
        self.reconcile_parts();
        Ok(PlanarReply {
            id,
            warning_id: ErrorId::NONE,
            value: ReplyValue::None,
        })
    }

    pub(super) fn disable_mover(&mut self, i: usize) -> Result<PlanarReply, Rejection> {
        let id = self.new_id();
        let t = self.timing;
        let ev_ = &mut self.pending;
        let m = &mut self.movers[i];
        let was_error = m.sm.in_error();
        let r = m.sm.disable(id, &t, ev_);
        if !was_error && r == Accepted::Started {
            for slot in [
                &mut m.xy_cmd,
                &mut m.c_cmd,
                &mut m.z_cmd,
                &mut m.a_cmd,
                &mut m.b_cmd,
                &mut m.halt_cmd,
            ] {
                end(ev_, slot, CommandState::Aborted);
            }
            if let Some(e) = m.esg.take() {
                ev(ev_, e.session, CommandState::Ended);
                if let Some(s) = e.stop_cmd {
                    ev(ev_, s, CommandState::Aborted);
                }
                m.offset.vel = MoverVector::default();
                m.offset.acc = MoverVector::default();
            }
            let (dxy, dc, da) = (
                m.cfg.default_dynamics,
                m.cfg.c_default_dynamics,
                m.cfg.aux_default_dynamics,
            );
            Self::plan_stops(m, &dxy, &dc, &da);
        }
        ev(
            ev_,
            id,
            if r == Accepted::AlreadyThere {
                CommandState::Done
            } else {
                CommandState::Active
            },
        );
        Ok(PlanarReply {
            id,
            warning_id: ErrorId::NONE,
            value: ReplyValue::None,
        })
    }

    pub(super) fn reset_mover(&mut self, i: usize) -> Result<PlanarReply, Rejection> {
        let who = format!("mover '{}'", self.movers[i].name);
        let id = self.new_id();
        let t = self.timing;
        let r = self.movers[i].sm.reset(id, &t, &who)?;
        if r == Accepted::AlreadyThere {
            ev(&mut self.pending, id, CommandState::Done);
        } else {
            ev(&mut self.pending, id, CommandState::Active);
            // §2.6: a mover Reset resets every erroneous part of its CS.
            let cs = self.movers[i].cs;
            for p in &mut self.parts {
                if p.origin().0 == cs && p.sm.state == PlanarState::Error {
                    p.sm.state = PlanarState::Resetting;
                    p.sm.hold(t.reset_time);
                }
            }
        }
        Ok(PlanarReply {
            id,
            warning_id: ErrorId::NONE,
            value: ReplyValue::None,
        })
    }

    pub(super) fn set_position(
        &mut self,
        i: usize,
        pos: PositionXYC,
    ) -> Result<PlanarReply, Rejection> {
        let who = format!("mover '{}'", self.movers[i].name);
        pos.check_finite(&who, "position")?;
        if self.movers[i].sm.state != PlanarState::Disabled {
            return Err(reject(
                E_INVALID_STATE,
                format!(
                    "{who}: SetPosition requires state Disabled, is {:?}",
                    self.movers[i].sm.state
                ),
            ));
        }
        let (cs, p) = self.resolve(&who, pos.x, pos.y, pos.reference_id)?;
        self.check_in_area(&who, cs, p)?;
        let m = &self.movers[i];
        let fp = ConvexPolygon::rect(p, m.cfg.width, m.cfg.height, pos.c);
        for j in 0..self.movers.len() {
            if j != i && self.movers[j].cs == cs && fp.intersects(&self.movers[j].envelope) {
                return Err(self.mover_collision(&who, j));
            }
        }
        let id = self.new_id();
        let m = &mut self.movers[i];
        m.cs = cs;
        m.xy = Kin2::at_rest(p);
        m.c = Axis1::at(pos.c);
        m.offset = Setpoint::default();
        m.envelope = m.footprint();
        ev(&mut self.pending, id, CommandState::Done);
        Ok(PlanarReply {
            id,
            warning_id: ErrorId::NONE,
            value: ReplyValue::None,
        })
    }

    pub(super) fn start_esg(
        &mut self,
        i: usize,
        options: ExternalSetpointGenerationOptions,
    ) -> Result<PlanarReply, Rejection> {
        let who = format!("mover '{}'", self.movers[i].name);
        self.require_enabled(i, "StartExternalSetpointGeneration")?;
        let kind = match options.mode {
            ExternalSetpointMode::Absolute => CommandKind::StartEsgAbsolute,
            ExternalSetpointMode::Relative => CommandKind::StartEsgRelative,
            m => {
                return Err(reject(
                    ErrorId::ENUM_OUT_OF_RANGE,
                    format!("{who}: options.mode = {m:?} is not Absolute or Relative"),
                ))
            }
        };
        self.require_mode(i, kind, "StartExternalSetpointGeneration")?;
        let id = self.new_id();
        let m = &mut self.movers[i];
        let here = m.pose();
        let last = match options.mode {
            ExternalSetpointMode::Absolute => Setpoint {
                pos: here,
                ..Default::default()
            },
            _ => m.offset,
        };
        m.esg = Some(Esg {
            mode: options.mode,
            session: id,
            stop_cmd: None,
            pending: None,
            last,
            missing: 0,
            stopping: false,
            stop_after_pending: false,
            fault: None,
        });
        if options.mode == ExternalSetpointMode::Absolute {
            m.mode = CommandMode::ExternalSetpointGeneration;
            end(&mut self.pending, &mut m.c_cmd, CommandState::Aborted);
            for slot in [&mut m.z_cmd, &mut m.a_cmd, &mut m.b_cmd] {
                end(&mut self.pending, slot, CommandState::Aborted);
            }
            for ax in [&mut m.c, &mut m.z, &mut m.a, &mut m.b] {
                *ax = Axis1::at(ax.pos);
            }
        }
        ev(&mut self.pending, id, CommandState::Active);
        Ok(PlanarReply {
            id,
            warning_id: ErrorId::NONE,
            value: ReplyValue::None,
        })
    }

    pub(super) fn stop_esg(&mut self, i: usize) -> Result<PlanarReply, Rejection> {
        self.require_mode(i, CommandKind::StopEsg, "StopExternalSetpointGeneration")?;
        let id = self.new_id();
        let m = &mut self.movers[i];
        let e = m.esg.as_mut().unwrap();
        if let Some(old) = e.stop_cmd.replace(id) {
            ev(&mut self.pending, old, CommandState::Aborted);
        }
        if e.mode == ExternalSetpointMode::Absolute {
            if e.pending.is_some() && !e.stopping {
                // §3.2: Stop follows the cycle's last set point, which is still applied.
                e.stop_after_pending = true;
            } else if !e.stopping {
                e.stopping = true;
                e.pending = None;
                let (dxy, dc, da) = (
                    m.cfg.max_dynamics,
                    m.cfg.c_max_dynamics,
                    m.cfg.aux_max_dynamics,
                );
                Self::plan_stops(m, &dxy, &dc, &da);
            }
        } else {
            // Relative (proposal): offsets frozen at their last value.
            let e = m.esg.take().unwrap();
            m.offset.vel = MoverVector::default();
            m.offset.acc = MoverVector::default();
            ev(&mut self.pending, e.session, CommandState::Ended);
            ev(&mut self.pending, id, CommandState::Done);
            return Ok(PlanarReply {
                id,
                warning_id: ErrorId::NONE,
                value: ReplyValue::None,
            });
        }
        ev(&mut self.pending, id, CommandState::Active);
        Ok(PlanarReply {
            id,
            warning_id: ErrorId::NONE,
            value: ReplyValue::None,
        })
    }

    pub(super) fn set_external_setpoint(
        &mut self,
        i: usize,
        sp: Setpoint,
        reference: Option<u32>,
    ) -> Result<PlanarReply, Rejection> {
        let who = format!("mover '{}'", self.movers[i].name);
        sp.pos.check_finite(&who, "set_position")?;
        sp.vel.check_finite(&who, "set_velocity")?;
        sp.acc.check_finite(&who, "set_acceleration")?;
        let m = &self.movers[i];
        let Some(e) = &m.esg else {
            return Err(reject(
                E_INVALID_COMMAND_MODE,
                format!("{who}: no external set-point generation is active"),
            ));
        };
        if e.stopping || e.stop_after_pending {
            return Err(reject(
                E_INVALID_COMMAND_MODE,
                format!("{who}: external set-point generation is stopping"),
            ));
        }
        let session = e.session;
        let mut sp = sp;
        let mut fault = None;
        if let Some(r) = reference {
            if e.mode == ExternalSetpointMode::Absolute {
                match self.resolve(&who, sp.pos.x, sp.pos.y, r) {
                    Ok((cs, p)) => {
                        let is_part = self.parts.iter().position(|x| x.oid == r);
                        if cs != m.cs {
                            fault = Some((E_INVALID_REFERENCE_ID, format!("{who}: set point in coordinate system 0x{cs:08X}, mover in 0x{:08X}", m.cs)));
                        } else if let Some(pi) =
                            is_part.filter(|&pi| !self.parts[pi].contains(cs, p))
                        {
                            fault = Some((E_INVALID_REFERENCE_ID, format!("{who}: set point ({}, {}) is not on part '{}' named by its ReferenceId", sp.pos.x, sp.pos.y, self.parts[pi].name)));
                        } else {
                            sp.pos.x = p.x;
                            sp.pos.y = p.y;
                        }
                    }
                    Err(rej) => fault = Some((E_INVALID_REFERENCE_ID, rej.message)),
                }
            }
        }
        let e = self.movers[i].esg.as_mut().unwrap();
        if let Some(f) = fault {
            e.fault.get_or_insert(f);
        } else {
            e.pending = Some(sp);
        }
        Ok(PlanarReply {
            id: session,
            warning_id: ErrorId::NONE,
            value: ReplyValue::None,
        })
    }

    pub(super) fn mover_add_to_group(
        &mut self,
        i: usize,
        gname: &str,
    ) -> Result<PlanarReply, Rejection> {
        let g = self.group(gname)?;
        let who = format!("mover '{}'", self.movers[i].name);
        if self.groups[g].sm.state != PlanarState::Enabled {
            return Err(reject(
                E_GROUP_NOT_READY,
                format!("{who}: group '{gname}' is {:?}", self.groups[g].sm.state),
            ));
        }
        self.require_enabled(i, "AddToGroup")?;
        self.require_mode(i, CommandKind::GroupMembership, "AddToGroup")?;
        if let Some(og) = self.movers[i].group {
            return Err(reject(
                E_GROUP_NOT_READY,
                format!("{who}: already member of group '{}'", self.groups[og].name),
            ));
        }
        let fp = self.movers[i].footprint();
        let cs = self.movers[i].cs;
        for k in 0..self.groups[g].movers.len() {
            let j = self.groups[g].movers[k];
            if self.movers[j].cs == cs && fp.intersects(&self.reservation(j)) {
                return Err(self.mover_collision(&who, j));
            }
        }
        let id = self.new_id();
        self.groups[g].movers.push(i);
        self.movers[i].group = Some(g);
        ev(&mut self.pending, id, CommandState::Done);
        Ok(PlanarReply {
            id,
            warning_id: ErrorId::NONE,
            value: ReplyValue::None,
        })
    }

    pub(super) fn mover_remove_from_group(&mut self, i: usize) -> Result<PlanarReply, Rejection> {
        let m = &self.movers[i];
        let mode_ok = matches!(m.mode, CommandMode::Invalid)
            || admissible(
                CommandKind::GroupMembership,
                m.mode,
                AdmissionContext {
                    standing: m.xy_standing(),
                    esg_active: m.esg.is_some(),
                },
            );
        if m.group.is_some() && !mode_ok {
            return Err(reject(
                E_INVALID_COMMAND_MODE,
                format!(
                    "mover '{}': RemoveFromGroup not allowed in command mode {:?} while moving",
                    m.name, m.mode
                ),
            ));
        }
        let id = self.new_id();
        if let Some(g) = self.movers[i].group.take() {
            self.groups[g].movers.retain(|&j| j != i);
            self.movers[i].reserved = None;
        }
        ev(&mut self.pending, id, CommandState::Done);
        Ok(PlanarReply {
            id,
            warning_id: ErrorId::NONE,
            value: ReplyValue::None,
        })
    }

    pub(super) fn position_on_current_part(&mut self, i: usize) -> Result<PlanarReply, Rejection> {
        let m = &self.movers[i];
        let Some(p) = self.part_of(m) else {
            return Err(reject(
                E_INVALID_PART,
                format!("mover '{}' is not on a part", m.name),
            ));
        };
        let (_, o) = self.parts[p].origin();
        let l = m.xy_out().pos - o;
        let value = ReplyValue::Position(PositionXYC::with_ref(
            l.x,
            l.y,
            m.c_out(),
            self.parts[p].oid,
        ));
        let id = self.new_id();
        ev(&mut self.pending, id, CommandState::Done);
        Ok(PlanarReply {
            id,
            warning_id: ErrorId::NONE,
            value,
        })
    }
}
