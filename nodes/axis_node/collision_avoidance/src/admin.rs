//! CA block admission (collision_avoidance.md §4.2 rules, §5): group administration,
//! validation in the order of §5.0, start/queue of motion commands, group halt/stop/disable.

use super::*;
impl CaGroups {
    // ------------------------------------------------------------------ commands

    /// One CA block call.
    pub fn command(
        &mut self,
        cmd: CaCommand,
        axes: &mut [Axis],
        index: &HashMap<String, usize>,
        fbs: &mut Handshake,
    ) -> Result<CaReply, Rejection> {
        match cmd {
            CaCommand::AddAxisToGroup {
                group,
                axis,
                ident_in_group,
            } => self.add_axis(&group, &axis, ident_in_group, axes, index, fbs),
            CaCommand::RemoveAxisFromGroup {
                group,
                ident_in_group,
            } => {
                let g = self.group_index(&group)?;
                self.not_stopping(g, "MC_RemoveAxisFromGroup")?;
                if let Some(k) = self.groups[g]
                    .members
                    .iter()
                    .position(|m| m.ident == ident_in_group.0)
                {
                    let ax = self.groups[g].members[k].axis;
                    if axes[ax].moving() {
                        return Err(rej(
                            err::AXIS_MOVING,
                            format!("MC_RemoveAxisFromGroup: axis '{}' is moving", axes[ax].name),
                        ));
                    }
                    self.remove_member(g, k, axes, fbs);
                }
                Ok(self.admin_reply(fbs))
            }
            CaCommand::UngroupAllAxes { group } => {
                let g = self.group_index(&group)?;
                self.disable(g, axes, fbs);
                while self.groups[g].n() > 0 {
                    let k = self.groups[g].n() - 1;
                    self.remove_member(g, k, axes, fbs);
                }
                Ok(self.admin_reply(fbs))
            }
            CaCommand::GroupEnable { group } => {
                let g = self.group_index(&group)?;
                use GroupState::*;
                match self.groups[g].state {
                    GroupErrorStop | GroupErrorDisabled => {
                        return Err(rej(
                            err::NOT_ALLOWED_IN_GROUP_STATE,
                            format!("MC_GroupEnable: group '{group}' is in an error state"),
                        ))
                    }
                    GroupDisabled => {
                        if self.groups[g].n() == 0 {
                            return Err(rej(
                                err::GROUP_EMPTY,
                                format!("MC_GroupEnable: group '{group}' has no axes"),
                            ));
                        }
                        let gr = &mut self.groups[g];
                        for m in &gr.members {
                            let a = &mut axes[m.axis];
                            a.abort_motion(fbs);
                            a.job = None;
                        }
                        gr.init_all_gaps(axes);
                        for m in &mut gr.members {
                            m.min_margin = f64::INFINITY;
                        }
                        gr.enable_requested = true;
                        let ready = gr.members.iter().all(|m| loop_closed(&axes[m.axis]));
                        gr.state = if ready { GroupStandby } else { GroupNotReady };
                    }
                    _ => {}
                }
                Ok(self.admin_reply(fbs))
            }
            CaCommand::GroupDisable { group } => {
                let g = self.group_index(&group)?;
                self.disable(g, axes, fbs);
                Ok(self.admin_reply(fbs))
            }
            CaCommand::GroupReset { group } => {
                let g = self.group_index(&group)?;
                let gr = &mut self.groups[g];
                let to = match gr.state {
                    GroupState::GroupErrorStop => Some(GroupState::GroupStandby),
                    GroupState::GroupErrorDisabled => Some(GroupState::GroupDisabled),
                    _ => None,
                };
                if let Some(to) = to {
                    gr.state = to;
                    gr.error_id = ErrorId::NONE;
                    for m in &gr.members {
                        let a = &mut axes[m.axis];
                        if !a.error_id.is_none() {
                            a.error_id = ErrorId::NONE;
                            if a.drive_fault {
                                a.drive_fault = false;
                                a.status_pending = a.controller_on;
                            }
                        }
                    }
                }
                Ok(self.admin_reply(fbs))
            }
            CaCommand::GroupReadStatus { group } => {
                let g = self.group_index(&group)?;
                let s = self.groups[g].status(axes);
                Ok(Self::value_reply(fbs, CaValue::Status(s)))
            }
            CaCommand::GroupReadError { group } => {
                let g = self.group_index(&group)?;
                let e = self.groups[g].error_id.0;
                Ok(Self::value_reply(fbs, CaValue::GroupErrorId(e)))
            }
            CaCommand::GroupSetOverride {
                group,
                enable,
                vel_factor,
            } => {
                let g = self.group_index(&group)?;
                let f = finite_or(
                    vel_factor,
                    err::PARAMETER_NOT_CORRECT,
                    "MC_GroupSetOverride.VelFactor",
                )?;
                let gr = &mut self.groups[g];
                if enable {
                    let f = f.clamp(0.0, 1.0);
                    gr.ovr_target = f;
                    gr.ovr_rate = if gr.cfg.override_ramp_time > 0.0 {
                        (f - gr.ovr_actual).abs() / gr.cfg.override_ramp_time
                    } else {
                        f64::INFINITY
                    };
                }
                let v = CaValue::Override {
                    enabled: enable,
                    actual_vel_factor: gr.ovr_actual,
                };
                Ok(Self::value_reply(fbs, v))
            }
            CaCommand::GroupHalt {
                group,
                deceleration,
                jerk,
            } => self.group_halt(&group, deceleration, jerk, false, axes, fbs),
            CaCommand::GroupStop {
                group,
                execute,
                deceleration,
                jerk,
            } => {
                if execute {
                    self.group_halt(&group, deceleration, jerk, true, axes, fbs)
                } else {
                    let g = self.group_index(&group)?;
                    if let Some(id) = self.groups[g].stop {
                        if let Some(i) = self.instances.get_mut(&id) {
                            i.execute = false;
                        }
                    }
                    Ok(Self::value_reply(
                        fbs,
                        CaValue::Status(self.groups[g].status(axes)),
                    ))
                }
            }
            CaCommand::MoveAbsolute(c) => {
                let (g, k) = self.member_of(&c.axis, index)?;
                self.motion_admissible(g, k, axes, "MC_MoveAbsoluteCA")?;
                let ad = self.groups[g].members[k].dynamics;
                let dy = resolve_move(&ad, c.velocity, c.acceleration, c.deceleration, c.jerk)?;
                let gap = self.resolve_gap(g, c.gap)?;
                let p = match c.position {
                    McLreal::Value(p) if p.is_finite() => p,
                    other => {
                        return Err(rej(
                            err::INVALID_TARGET_POSITION,
                            format!("MC_MoveAbsoluteCA.Position = {other:?} is not a valid target"),
                        ))
                    }
                };
                let cfg = &self.groups[g].cfg;
                // An active track: Position is a track coordinate (§5.6).
                let p = match cfg.geometry.track(self.groups[g].members[k].track) {
                    None => p,
                    Some(t) => {
                        let origin = cfg.geometry.part(t.parts[0]).map_or(0.0, |q| q.start);
                        if c.direction == CaDirection::NonModulo {
                            p + origin
                        } else if (0.0..=cfg.rail_length).contains(&p) {
                            (p + origin).rem_euclid(cfg.rail_length)
                        } else {
                            return Err(rej(
                                err::INVALID_TARGET_POSITION,
                                format!("modulo track target {p} outside [0, {}]", cfg.rail_length),
                            ));
                        }
                    }
                };
                // A template reference system: Position is an offset-path coordinate (§5.9).
                let p = match c.position_reference_system {
                    0 => p,
                    oid => {
                        let path = self.groups[g].reference_path(k, oid)?;
                        if c.direction == CaDirection::NonModulo {
                            path.from_offset(p)
                        } else {
                            let lap = path.to_offset(cfg.rail_length);
                            if !(0.0..=lap).contains(&p) {
                                return Err(rej(
                                    err::INVALID_TARGET_POSITION,
                                    format!("modulo offset-path target {p} outside [0, {lap}]"),
                                ));
                            }
                            path.from_offset(p).rem_euclid(cfg.rail_length)
                        }
                    }
                };
                let x0 = axes[self.groups[g].members[k].axis].set.pos;
                let target = modulo::target(
                    x0,
                    cfg.rail_length,
                    axes[self.groups[g].members[k].axis]
                        .cfg
                        .modulo_tolerance_window,
                    p,
                    c.direction,
                    c.additional_turns,
                    cfg.rail_is_ring,
                )?;
                let req = Request {
                    owner: None,
                    goal: Goal::Absolute(target),
                    dy,
                    gap,
                    mode: c.gap_control_mode,
                    continuous_update: c.continuous_update,
                    dyn_path: self.groups[g].dyn_path(k, c.dynamics_reference_system)?,
                };
                self.start(g, k, req, c.buffer_mode, CaFbKind::MoveAbsolute, axes, fbs)
            }
            CaCommand::MoveRelative(c) => {
                let (g, k) = self.member_of(&c.axis, index)?;
                self.motion_admissible(g, k, axes, "MC_MoveRelativeCA")?;
                let ad = self.groups[g].members[k].dynamics;
                let dy = resolve_move(&ad, c.velocity, c.acceleration, c.deceleration, c.jerk)?;
                let gap = self.resolve_gap(g, c.gap)?;
                let d = match c.distance {
                    McLreal::Value(d) if d.is_finite() => d,
                    other => {
                        return Err(rej(
                            err::INVALID_TARGET_POSITION,
                            format!("MC_MoveRelativeCA.Distance = {other:?} is not valid"),
                        ))
                    }
                };
                let req = Request {
                    owner: None,
                    goal: match c.position_reference_system {
                        0 => Goal::Relative(d),
                        oid => Goal::RelativeOffset(d, self.groups[g].reference_path(k, oid)?),
                    },
                    dy,
                    gap,
                    mode: c.gap_control_mode,
                    continuous_update: c.continuous_update,
                    dyn_path: self.groups[g].dyn_path(k, c.dynamics_reference_system)?,
                };
                self.start(g, k, req, c.buffer_mode, CaFbKind::MoveRelative, axes, fbs)
            }
            CaCommand::Halt(c) => {
                let (g, k) = self.member_of(&c.axis, index)?;
                self.motion_admissible(g, k, axes, "MC_HaltCA")?;
                let ad = self.groups[g].members[k].dynamics;
                let d = resolve_acc(c.deceleration, ad.def_d, ad.max_d, "Deceleration")?;
                let j = resolve_jerk(c.jerk, ad.def_j, ad.max_j, false)?;
                let gap = self.resolve_gap(g, c.gap)?;
                let req = Request {
                    owner: None,
                    goal: Goal::Brake,
                    dy: Dyn {
                        v: ad.max_v,
                        a: ad.max_a,
                        d,
                        j,
                    },
                    gap,
                    mode: c.gap_control_mode,
                    continuous_update: false,
                    dyn_path: self.groups[g].dyn_path(k, c.dynamics_reference_system)?,
                };
                self.start(g, k, req, CaBufferMode::Aborting, CaFbKind::Halt, axes, fbs)
            }
            CaCommand::GearInPos(c) => {
                let fb = "MC_GearInPosCA";
                let (g, k) = self.member_of(&c.slave, index)?;
                self.motion_admissible(g, k, axes, fb)?;
                let master = *index.get(&c.master).ok_or_else(|| {
                    rej(
                        err::AXIS_NOT_IN_GROUP,
                        format!("{fb}: unknown master '{}'", c.master),
                    )
                })?;
                if master == self.groups[g].members[k].axis {
                    return Err(rej(
                        err::PARAMETER_NOT_CORRECT,
                        format!("{fb}: Master = Slave"),
                    ));
                }
                let pos = |x: McLreal, what: &str| match x {
                    McLreal::Value(v) if v.is_finite() => Ok(v),
                    other => Err(rej(
                        err::INVALID_TARGET_POSITION,
                        format!("{fb}.{what} = {other:?}"),
                    )),
                };
                let msp = pos(c.master_sync_position, "MasterSyncPosition")?;
                let ssp = pos(c.slave_sync_position, "SlaveSyncPosition")?;
                let cfg = &self.groups[g].cfg;
                let x = axes[self.groups[g].members[k].axis].set.pos;
                // SlaveSyncPositionReferenceSystem: an offset-path coordinate (§5.9), taken
                // to the motor path; a modulo value lies within one offset-path lap.
                let ssp_path = match c.slave_sync_position_reference_system {
                    0 => None,
                    oid => Some(self.groups[g].reference_path(k, oid)?),
                };
                let lap = ssp_path.map_or(cfg.rail_length, |p| p.to_offset(cfg.rail_length));
                let to_motor = |v: f64| ssp_path.map_or(v, |p| p.from_offset(v));
                let ssp = match c.sync_mode {
                    SyncMode::NonModulo => to_motor(ssp),
                    _ if !cfg.rail_is_ring => {
                        return Err(rej(
                            err::MODULO_ON_OPEN_RAIL,
                            format!("{fb}: SyncMode {:?} needs a ring", c.sync_mode),
                        ))
                    }
                    _ if !(0.0..lap).contains(&ssp) => {
                        return Err(rej(
                            err::INVALID_TARGET_POSITION,
                            format!("{fb}: modulo SlaveSyncPosition {ssp} outside [0, {lap})"),
                        ))
                    }
                    mode => {
                        let ssp = to_motor(ssp).rem_euclid(cfg.rail_length);
                        if mode == SyncMode::Positive {
                            x + (ssp - x).rem_euclid(cfg.rail_length)
                        } else {
                            x - (x - ssp).rem_euclid(cfg.rail_length)
                        }
                    }
                };
                let start_distance = match c.master_start_distance {
                    McLreal::Unset | McLreal::Ignore => None,
                    McLreal::Value(d) if d.is_finite() => Some(d),
                    other => {
                        return Err(rej(
                            err::PARAMETER_NOT_CORRECT,
                            format!("{fb}.MasterStartDistance = {other:?}"),
                        ))
                    }
                };
                if c.forbid_master_velocity_undershoot && c.forbid_master_velocity_overshoot {
                    return Err(rej(
                        err::INVALID_SYNC_OPTIONS,
                        format!("{fb}: undershoot and overshoot both forbidden"),
                    ));
                }
                let min_pos = match c.minimal_slave_position {
                    McLreal::Unset | McLreal::Ignore => f64::NEG_INFINITY,
                    McLreal::Value(v) if v.is_finite() => v,
                    other => {
                        return Err(rej(
                            err::INVALID_SYNC_OPTIONS,
                            format!("{fb}.MinimalSlavePosition = {other:?}"),
                        ))
                    }
                };
                let num = match c.ratio_numerator {
                    McLreal::Unset | McLreal::Default => 1.0,
                    McLreal::Value(v) if v.is_finite() => v,
                    other => {
                        return Err(rej(
                            err::PARAMETER_NOT_CORRECT,
                            format!("{fb}.RatioNumerator = {other:?}"),
                        ))
                    }
                };
                if c.ratio_denumerator == 0 {
                    return Err(rej(
                        err::PARAMETER_NOT_CORRECT,
                        format!("{fb}.RatioDenumerator = 0"),
                    ));
                }
                let ad = self.groups[g].members[k].dynamics;
                let dy = resolve_move(&ad, c.velocity, c.acceleration, c.deceleration, c.jerk)?;
                let gap = self.resolve_gap(g, c.gap)?;
                let after_default = match self.groups[g].cfg.gear_in_pos_default_dynamics_after_sync
                {
                    DynamicsAfterSync::JobDynamics => dy,
                    DynamicsAfterSync::MaximumSlaveDynamics => Dyn {
                        v: ad.max_v,
                        a: ad.max_a,
                        d: ad.max_d,
                        j: JERK_UNLIMITED,
                    },
                };
                let after = Dyn {
                    v: match c.after_sync_velocity {
                        McLreal::Unset | McLreal::Default => after_default.v,
                        McLreal::Maximum => ad.max_v,
                        McLreal::Value(v) if v.is_finite() && v > 0.0 => v.min(ad.max_v),
                        other => {
                            return Err(rej(
                                err::INVALID_VELOCITY,
                                format!("{fb}.AfterSyncVelocity = {other:?}"),
                            ))
                        }
                    },
                    a: match c.after_sync_acceleration {
                        McLreal::Unset | McLreal::Default => after_default.a,
                        x => resolve_acc(x, ad.def_a, ad.max_a, "AfterSyncAcceleration")?,
                    },
                    d: match c.after_sync_deceleration {
                        McLreal::Unset | McLreal::Default => after_default.d,
                        x => resolve_acc(x, ad.def_d, ad.max_d, "AfterSyncDeceleration")?,
                    },
                    j: match c.after_sync_jerk {
                        McLreal::Unset | McLreal::Default => after_default.j,
                        x => resolve_jerk(x, ad.def_j, ad.max_j, false)?,
                    },
                };
                // DynamicsReferenceSystem: the coupling runs on the offset path (§5.9).
                let dyn_path = self.groups[g].dyn_path(k, c.dynamics_reference_system)?;
                let work = |v: f64| dyn_path.map_or(v, |p| p.to_offset(v));
                let gear = Gear {
                    master,
                    ratio: num / c.ratio_denumerator as f64,
                    msp,
                    ssp: work(ssp),
                    strategy: c.sync_strategy,
                    started: false,
                    start_distance,
                    keep_cam: c.override_slave_dynamic_restrictions,
                    after,
                    ever_in_sync: false,
                    in_sync: false,
                    failed: false,
                    cam: None,
                    late_start: None,
                    limits: SyncLimits {
                        min_pos: if min_pos.is_finite() {
                            work(min_pos)
                        } else {
                            min_pos
                        },
                        no_reversal: c.forbid_direction_reversal,
                        no_undershoot: c.forbid_master_velocity_undershoot,
                        no_overshoot: c.forbid_master_velocity_overshoot,
                    },
                    target: x,
                };
                let req = Request {
                    owner: None,
                    goal: Goal::Gear(gear),
                    dy,
                    gap,
                    mode: c.gap_control_mode,
                    continuous_update: c.continuous_update,
                    dyn_path,
                };
                self.start(g, k, req, c.buffer_mode, CaFbKind::GearInPos, axes, fbs)
            }
            CaCommand::UpdateGap { axis, gap } => {
                let (g, k) = self.member_of(&axis, index)?;
                let gap = self.resolve_gap(g, gap)?;
                let m = &mut self.groups[g].members[k];
                match &mut m.job {
                    Job::Position { req, .. } | Job::Brake { req } | Job::Gear { req, .. }
                        if req.continuous_update =>
                    {
                        req.gap = gap;
                        Ok(Self::value_reply(fbs, CaValue::GroupErrorId(0)))
                    }
                    _ => Err(rej(
                        err::CONTINUOUS_UPDATE_NOT_ENABLED,
                        format!(
                            "update_gap: axis '{axis}' has no active command with ContinuousUpdate"
                        ),
                    )),
                }
            }
            CaCommand::ActivateTrack { axis, track_id } => {
                let (g, k) = self.member_of(&axis, index)?;
                let gr = &self.groups[g];
                if track_id != 0 {
                    let geo = &gr.cfg.geometry;
                    let t = geo.track(track_id).ok_or_else(|| {
                        rej(
                            err::TRACK_ERROR,
                            format!("MC_ActivateTrack: unknown track {track_id:#x}"),
                        )
                    })?;
                    let x = axes[gr.members[k].axis].set.pos;
                    let on = geo
                        .part_at(x, gr.cfg.rail_length, gr.cfg.rail_is_ring)
                        .is_some_and(|p| t.parts.contains(&p.oid));
                    if !on {
                        return Err(rej(
                            err::TRACK_ERROR,
                            format!("MC_ActivateTrack: axis '{axis}' is not on a part of track {track_id:#x}"),
                        ));
                    }
                }
                self.groups[g].members[k].track = track_id;
                Ok(self.admin_reply(fbs))
            }
            CaCommand::ReadTrackPositions { axis } => {
                let (g, k) = self.member_of(&axis, index)?;
                let gr = &self.groups[g];
                let (l, ring) = (gr.cfg.rail_length, gr.cfg.rail_is_ring);
                let geo = &gr.cfg.geometry;
                let x = axes[gr.members[k].axis].set.pos;
                let wrap = |d: f64| if ring { d.rem_euclid(l) } else { d };
                let v = match geo.track(gr.members[k].track) {
                    None => CaValue::TrackPositions {
                        valid: true,
                        track_position: x,
                        track_id: 0,
                        part_position: x,
                        part_id: 0,
                    },
                    Some(t) => {
                        let origin = geo.part(t.parts[0]).map_or(0.0, |q| q.start);
                        let part = geo.part_at(x, l, ring);
                        CaValue::TrackPositions {
                            valid: true,
                            track_position: wrap(x - origin),
                            track_id: t.oid,
                            part_position: part.map_or(f64::NAN, |p| wrap(x - p.start)),
                            part_id: part.map_or(0, |p| p.oid),
                        }
                    }
                };
                Ok(Self::value_reply(fbs, v))
            }
            CaCommand::RegisterCompensation {
                axis,
                compensation_type,
                compensation_id,
            } => {
                let (g, k) = self.member_of(&axis, index)?;
                if compensation_type != 1 {
                    return Err(rej(
                        err::INVALID_MODE,
                        format!("MC_RegisterCompensation: CompensationType = {compensation_type} is not geo (1)"),
                    ));
                }
                if compensation_id != 0 {
                    self.groups[g].cfg.geometry.y_shift(compensation_id)?;
                }
                self.groups[g].members[k].compensation = compensation_id;
                Ok(self.admin_reply(fbs))
            }
            CaCommand::TransformPosition {
                group,
                origin_oid,
                destination_oid,
                origin_position,
            } => {
                let g = self.group_index(&group)?;
                let x = match origin_position {
                    McLreal::Value(x) if x.is_finite() => x,
                    other => {
                        return Err(rej(
                            err::INVALID_TARGET_POSITION,
                            format!("MC_TransformPosition.OriginPosition = {other:?}"),
                        ))
                    }
                };
                let cfg = &self.groups[g].cfg;
                let y = cfg
                    .geometry
                    .transform(cfg.rail_length, origin_oid, destination_oid, x)?;
                Ok(Self::value_reply(fbs, CaValue::Position(y)))
            }
            CaCommand::SetTemplateActive { group, oid, active } => {
                let g = self.group_index(&group)?;
                let t = self.groups[g]
                    .cfg
                    .geometry
                    .mover_templates
                    .iter_mut()
                    .find(|t| t.oid == oid)
                    .ok_or_else(|| {
                        rej(
                            err::COMPENSATION_ERROR,
                            format!("unknown mover template {oid:#x}"),
                        )
                    })?;
                t.active = active;
                Ok(self.admin_reply(fbs))
            }
            CaCommand::ResetDiagnostics { group } => {
                let g = self.group_index(&group)?;
                for m in &mut self.groups[g].members {
                    m.min_margin = f64::INFINITY;
                }
                Ok(self.admin_reply(fbs))
            }
        }
    }

    pub(super) fn not_stopping(&self, g: usize, fb: &str) -> Result<(), Rejection> {
        if self.groups[g].state == GroupState::GroupStopping {
            Err(rej(
                err::NOT_ALLOWED_IN_GROUP_STATE,
                format!("{fb}: group '{}' is Stopping", self.groups[g].name),
            ))
        } else {
            Ok(())
        }
    }

    pub(super) fn member_of(
        &self,
        axis: &str,
        index: &HashMap<String, usize>,
    ) -> Result<(usize, usize), Rejection> {
        let not_in = || {
            rej(
                err::AXIS_NOT_IN_GROUP,
                format!("axis '{axis}' is not in a CA group"),
            )
        };
        let ax = *index.get(axis).ok_or_else(not_in)?;
        let g = *self.axis_group.get(&ax).ok_or_else(not_in)?;
        let k = self.groups[g]
            .members
            .iter()
            .position(|m| m.axis == ax)
            .ok_or_else(not_in)?;
        Ok((g, k))
    }

    pub(super) fn motion_admissible(
        &self,
        g: usize,
        k: usize,
        axes: &[Axis],
        fb: &str,
    ) -> Result<(), Rejection> {
        let gr = &self.groups[g];
        if !matches!(gr.state, GroupState::GroupStandby | GroupState::GroupMoving) {
            return Err(rej(
                err::NOT_ALLOWED_IN_GROUP_STATE,
                format!("{fb}: group '{}' is {:?}", gr.name, gr.state),
            ));
        }
        let a = &axes[gr.members[k].axis];
        if !(loop_closed(a) && a.enable_positive && a.enable_negative) {
            return Err(rej(
                err::AXIS_NOT_READY,
                format!("{fb}: axis '{}' has no closed loop or feed enables", a.name),
            ));
        }
        Ok(())
    }

    pub(super) fn resolve_gap(&self, g: usize, gap: McLreal) -> Result<f64, Rejection> {
        let cfg = &self.groups[g].cfg;
        match gap {
            McLreal::Unset | McLreal::Default => Ok(cfg.default_gap),
            McLreal::Value(v)
                if v.is_finite() && v >= 0.0 && !(cfg.rail_is_ring && v >= cfg.rail_length) =>
            {
                Ok(v)
            }
            other => Err(rej(
                err::INVALID_GAP,
                format!("Gap = {other:?} is not valid"),
            )),
        }
    }

    #[allow(clippy::too_many_arguments)]
    pub(super) fn start(
        &mut self,
        g: usize,
        k: usize,
        mut req: Request,
        mode: CaBufferMode,
        kind: CaFbKind,
        axes: &[Axis],
        fbs: &mut Handshake,
    ) -> Result<CaReply, Rejection> {
        let m = &self.groups[g].members[k];
        let buffered = mode == CaBufferMode::Buffered && m.job.owner().is_some();
        if buffered && m.pending.is_some() {
            return Err(rej(
                err::BUFFER_FULL,
                "a buffered command is already waiting on this axis",
            ));
        }
        // A new motion command ends a running group halt (not locking, §1.8).
        if let Some(h) = self.groups[g].halt.take() {
            self.set_state(fbs, h, CommandState::Aborted);
        }
        let state = if buffered {
            CommandState::Busy
        } else {
            CommandState::Active
        };
        let id = self.admit(fbs, kind, state);
        req.owner = Some(id);
        if buffered {
            self.groups[g].members[k].pending = Some(req);
        } else {
            self.end_member(fbs, g, k, CommandState::Aborted);
            let x = axes[self.groups[g].members[k].axis].set.pos;
            self.groups[g].members[k].job = activate(req, x);
            if self.groups[g].state == GroupState::GroupStandby {
                self.groups[g].state = GroupState::GroupMoving;
            }
        }
        Ok(CaReply {
            id,
            value: None,
            tracked: true,
        })
    }

    pub(super) fn group_halt(
        &mut self,
        group: &str,
        dec: McLreal,
        jerk: McLreal,
        stop: bool,
        axes: &[Axis],
        fbs: &mut Handshake,
    ) -> Result<CaReply, Rejection> {
        let g = self.group_index(group)?;
        let fb = if stop { "MC_GroupStop" } else { "MC_GroupHalt" };
        use GroupState::*;
        let st = self.groups[g].state;
        let ok = if stop {
            matches!(st, GroupStandby | GroupMoving | GroupNotReady)
        } else {
            matches!(st, GroupStandby | GroupMoving)
        };
        if !ok {
            return Err(rej(
                err::NOT_ALLOWED_IN_GROUP_STATE,
                format!("{fb}: group '{group}' is {st:?}"),
            ));
        }
        // Validate the markers once (per-axis resolution below cannot fail then).
        match dec {
            McLreal::Value(v) if !(v.is_finite() && v >= 1.0) => {
                return Err(rej(
                    err::INVALID_DYNAMICS,
                    format!("{fb}.Deceleration = {v}"),
                ))
            }
            McLreal::Ignore => {
                return Err(rej(
                    err::INVALID_DYNAMICS,
                    format!("{fb}.Deceleration = IGNORE"),
                ))
            }
            _ => {}
        }
        if let McLreal::Value(v) = jerk {
            if !(v.is_finite() && v >= 100.0) {
                return Err(rej(err::INVALID_DYNAMICS, format!("{fb}.Jerk = {v}")));
            }
        }
        self.end_group_blocks(fbs, g, CommandState::Aborted);
        for k in 0..self.groups[g].n() {
            self.end_member(fbs, g, k, CommandState::Aborted);
            let m = &mut self.groups[g].members[k];
            let ad = m.dynamics;
            let d = resolve_acc(dec, ad.def_d, ad.max_d, "Deceleration").unwrap_or(ad.def_d);
            let j = match jerk {
                McLreal::Ignore => JERK_UNLIMITED,
                McLreal::Maximum => ad.max_j,
                other => resolve_jerk(other, ad.def_j, ad.max_j, false).unwrap_or(ad.def_j),
            };
            if axes[m.axis].moving() {
                m.job = Job::Brake {
                    req: Request {
                        owner: None,
                        goal: Goal::Brake,
                        dy: Dyn {
                            v: ad.max_v,
                            a: ad.max_a,
                            d,
                            j,
                        },
                        gap: m.last_gap,
                        mode: GapControlMode::GroupDefault,
                        continuous_update: false,
                        dyn_path: None,
                    },
                };
            }
        }
        let kind = if stop {
            CaFbKind::GroupStop
        } else {
            CaFbKind::GroupHalt
        };
        let id = self.admit(fbs, kind, CommandState::Active);
        let gr = &mut self.groups[g];
        if stop {
            gr.stop = Some(id);
            gr.stop_done = false;
            gr.state = GroupStopping;
        } else {
            gr.halt = Some(id);
            if gr.busy() {
                gr.state = GroupMoving;
            }
        }
        Ok(CaReply {
            id,
            value: None,
            tracked: true,
        })
    }

    pub(super) fn add_axis(
        &mut self,
        group: &str,
        axis: &str,
        ident: IdentInGroup,
        axes: &mut [Axis],
        index: &HashMap<String, usize>,
        fbs: &mut Handshake,
    ) -> Result<CaReply, Rejection> {
        let g = self.group_index(group)?;
        self.not_stopping(g, "MC_AddAxisToGroup")?;
        let ax = *index.get(axis).ok_or_else(|| {
            rej(
                err::AXIS_NOT_IN_GROUP,
                format!("MC_AddAxisToGroup: unknown axis '{axis}'"),
            )
        })?;
        let gr = &self.groups[g];
        if ident.0 == 0 || gr.members.iter().any(|m| m.ident == ident.0) {
            return Err(rej(
                err::INVALID_IDENT_IN_GROUP,
                format!(
                    "MC_AddAxisToGroup: IdentInGroup {} is 0 or already used",
                    ident.0
                ),
            ));
        }
        if let Some(&other) = self.axis_group.get(&ax) {
            return Err(rej(
                err::AXIS_IN_OTHER_GROUP,
                format!(
                    "MC_AddAxisToGroup: axis '{axis}' already belongs to group '{}'",
                    self.groups[other].name
                ),
            ));
        }
        if gr.enabled() && axes[ax].moving() {
            return Err(rej(
                err::AXIS_MOVING,
                format!("MC_AddAxisToGroup: axis '{axis}' is moving"),
            ));
        }
        if gr.enabled() {
            axes[ax].abort_motion(fbs);
            axes[ax].job = None;
        }
        let gr = &mut self.groups[g];
        let key = |x: f64| {
            if gr.cfg.rail_is_ring {
                x.rem_euclid(gr.cfg.rail_length)
            } else {
                x
            }
        };
        let u = key(axes[ax].set.pos);
        // Front first; ties: the new axis goes in front of the tied ones (§1.2).
        let k = gr
            .members
            .iter()
            .position(|m| key(axes[m.axis].set.pos) <= u)
            .unwrap_or(gr.n());
        let ad = AxisDyn::of(&axes[ax]);
        gr.members.insert(
            k,
            Member {
                axis: ax,
                ident: ident.0,
                dynamics: ad,
                gap: f64::NAN,
                job: Job::Idle,
                pending: None,
                last_gap: gr.cfg.default_gap,
                d_ca: ad.def_d,
                j_ca: ad.def_j,
                d_b: ad.def_d,
                j_b: ad.def_j,
                ca_limited: false,
                min_margin: f64::INFINITY,
                updated: false,
                retreat: 0.0,
                track: 0,
                compensation: 0,
            },
        );
        gr.init_all_gaps(axes);
        self.axis_group.insert(ax, g);
        Ok(self.admin_reply(fbs))
    }

    pub(super) fn remove_member(
        &mut self,
        g: usize,
        k: usize,
        axes: &mut [Axis],
        fbs: &mut Handshake,
    ) {
        self.end_member(fbs, g, k, CommandState::Aborted);
        let gr = &mut self.groups[g];
        let m = gr.members.remove(k);
        axes[m.axis].set.vel = 0.0;
        axes[m.axis].set.acc = 0.0;
        axes[m.axis].target_pos = axes[m.axis].set.pos;
        self.axis_group.remove(&m.axis);
        gr.init_all_gaps(axes);
        if gr.n() == 0 {
            gr.enable_requested = false;
            gr.state = match gr.state {
                GroupState::GroupErrorStop | GroupState::GroupErrorDisabled => {
                    GroupState::GroupErrorDisabled
                }
                _ => GroupState::GroupDisabled,
            };
        }
    }

    /// MC_GroupDisable (§5.13): instant stop, all commands aborted.
    pub(super) fn disable(&mut self, g: usize, axes: &mut [Axis], fbs: &mut Handshake) {
        self.end_group_blocks(fbs, g, CommandState::Aborted);
        for k in 0..self.groups[g].n() {
            self.end_member(fbs, g, k, CommandState::Aborted);
            let a = &mut axes[self.groups[g].members[k].axis];
            a.set.vel = 0.0;
            a.set.acc = 0.0;
            a.target_pos = a.set.pos;
        }
        let gr = &mut self.groups[g];
        gr.enable_requested = false;
        gr.state = match gr.state {
            GroupState::GroupErrorStop | GroupState::GroupErrorDisabled => {
                GroupState::GroupErrorDisabled
            }
            _ => GroupState::GroupDisabled,
        };
    }
}

/// Velocity/Acceleration/Deceleration/Jerk of a CA move (§5.1), clamped to the maxima.
pub(super) fn resolve_move(
    ad: &AxisDyn,
    v: McLreal,
    a: McLreal,
    d: McLreal,
    j: McLreal,
) -> Result<Dyn, Rejection> {
    let v = match v {
        McLreal::Value(v) if v.is_finite() && v > 0.0 => v.min(ad.max_v),
        McLreal::Maximum => ad.max_v,
        other => {
            return Err(rej(
                err::INVALID_VELOCITY,
                format!("Velocity = {other:?} is not valid (> 0 required)"),
            ))
        }
    };
    Ok(Dyn {
        v,
        a: resolve_acc(a, ad.def_a, ad.max_a, "Acceleration")?,
        d: resolve_acc(d, ad.def_d, ad.max_d, "Deceleration")?,
        j: resolve_jerk(j, ad.def_j, ad.max_j, false)?,
    })
}

pub(super) fn resolve_acc(x: McLreal, def: f64, max: f64, what: &str) -> Result<f64, Rejection> {
    match x {
        McLreal::Unset | McLreal::Default => Ok(def),
        McLreal::Maximum => Ok(max),
        McLreal::Value(v) if v.is_finite() && v >= 1.0 => Ok(v.min(max)),
        other => Err(rej(
            err::INVALID_DYNAMICS,
            format!("{what} = {other:?} is not valid (>= 1 required)"),
        )),
    }
}

pub(super) fn resolve_jerk(
    x: McLreal,
    def: f64,
    max: f64,
    ignore_ok: bool,
) -> Result<f64, Rejection> {
    match x {
        McLreal::Unset | McLreal::Default => Ok(def),
        McLreal::Ignore if ignore_ok => Ok(JERK_UNLIMITED),
        McLreal::Value(v) if v.is_finite() && v >= 100.0 => Ok(v.min(max)),
        other => Err(rej(
            err::INVALID_DYNAMICS,
            format!("Jerk = {other:?} is not valid (>= 100 required, MAXIMUM not allowed)"),
        )),
    }
}
