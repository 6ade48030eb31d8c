//! The objects' construction from the configuration, lookups, the admission checks shared by
//! the commands, collisions and swept-area checks, snapshots and cancel.

use super::*;

impl Objects {
    /// The objects of `cfg` (environment, parts, movers, groups); `PlanarEngine::new`
    /// (build.rs) adds the track subsystem.
    pub(crate) fn build(cfg: &PlanarConfig) -> Result<Self, Rejection> {
        cfg.validate()?;
        let (env_oid, mover_oids, group_oids) = cfg.resolved_oids();
        let timing = Timing {
            enable_time: cfg.enable_time,
            disable_time: cfg.disable_time,
            reset_time: cfg.reset_time,
            error_pending_time: cfg.error_pending_time,
        };
        let parts: Vec<Part> = cfg
            .parts
            .iter()
            .map(|p| Part {
                name: p.name.clone(),
                oid: p.oid,
                tiles: p.tiles.iter().map(|t| V2::new(t[0], t[1])).collect(),
                positions: p.positions.clone(),
                index: p.initial_index,
                sm: PlanarStateMachine::default(),
                initialized: false,
                force_disabled: false,
                transit: None,
            })
            .collect();
        let mut movers = Vec::with_capacity(cfg.movers.len());
        let mut max_diag: f64 = 1.0;
        for (i, m) in cfg.movers.iter().enumerate() {
            let (cs, origin) = if parts.is_empty() {
                (
                    cfg.coordinate_systems.first().copied().unwrap_or(0),
                    V2::zeros(),
                )
            } else {
                let p = if m.part_oid == 0 {
                    &parts[0]
                } else {
                    parts.iter().find(|p| p.oid == m.part_oid).unwrap()
                };
                p.origin()
            };
            let pos = origin + V2::new(m.initial_pose.x, m.initial_pose.y);
            let mut mv = Mover {
                name: m.name.clone(),
                oid: mover_oids[i],
                cfg: m.clone(),
                sm: PlanarStateMachine::default(),
                object_info: PlanarObjectInfo::default(),
                mode: CommandMode::Invalid,
                cs,
                xy: Kin2::at_rest(pos),
                path: None,
                c: Axis1::at(m.initial_pose.c),
                z: Axis1::at(m.z_range[0].max(0.0).min(m.z_range[1])),
                a: Axis1::at(0.0f64.clamp(m.a_range[0], m.a_range[1])),
                b: Axis1::at(0.0f64.clamp(m.b_range[0], m.b_range[1])),
                xy_cmd: None,
                c_cmd: None,
                z_cmd: None,
                a_cmd: None,
                b_cmd: None,
                halt_cmd: None,
                guard_stop: false,
                esg: None,
                offset: Setpoint::default(),
                group: None,
                reserved: None,
                envelope: ConvexPolygon::aabb_box(V2::zeros(), V2::zeros()),
                warning: ErrorId::NONE,
                c_mode: CCoordinateMode::Independent,
                track: None,
                joining: None,
                leaving: None,
            };
            mv.envelope = mv.footprint();
            max_diag = max_diag.max(mv.diag());
            movers.push(mv);
        }
        let groups = cfg
            .groups
            .iter()
            .enumerate()
            .map(|(i, g)| Group {
                name: g.name.clone(),
                oid: group_oids[i],
                sm: PlanarStateMachine::default(),
                movers: vec![],
                environment: false,
            })
            .collect::<Vec<_>>();
        let mover_idx = movers
            .iter()
            .enumerate()
            .map(|(i, m)| (m.name.clone(), i))
            .collect();
        let group_idx = groups
            .iter()
            .enumerate()
            .map(|(i, g)| (g.name.clone(), i))
            .collect();
        let part_idx = parts
            .iter()
            .enumerate()
            .map(|(i, p)| (p.name.clone(), i))
            .collect();
        let objects = Objects {
            timing,
            cycle_time: cfg.cycle_time,
            part_move_time: cfg.part_move_time,
            esg_timeout_cycles: cfg.esg_timeout_cycles,
            time: 0.0,
            coordinate_systems: if cfg.coordinate_systems.is_empty() {
                vec![0]
            } else {
                cfg.coordinate_systems.clone()
            },
            env: Environment {
                name: cfg.environment.name.clone(),
                oid: env_oid,
                processing_unit_oid: cfg.environment.processing_unit_oid,
                stators: vec![],
                boundary: None,
                group: None,
            },
            parts,
            movers,
            groups,
            mover_idx,
            group_idx,
            part_idx,
            next_id: 1,
            pending: Vec::new(),
            grid: Grid::new(2.0 * max_diag),
            scratch: Vec::new(),
            last_object_info: PlanarObjectInfo::default(),
            guard_full: true,
        };
        Ok(objects)
    }

    /// The configured cycle time \[s\].
    pub(crate) fn cycle_time(&self) -> f64 {
        self.cycle_time
    }

    /// `objectInfo` of the last E_COLLISION (rejection or guard stop): the blocking object (§6.1).
    pub(crate) fn last_object_info(&self) -> PlanarObjectInfo {
        self.last_object_info
    }

    /// Converts a position with ReferenceId (CS OID, part OID or 0) into its coordinate
    /// system (§1.3, §1.4); the result's `reference_id` is the CS OID.
    pub(crate) fn resolve_position(&self, p: &PositionXYC) -> Result<PositionXYC, Rejection> {
        p.check_finite("resolve_position", "position")?;
        let (cs, v) = self.resolve("resolve_position", p.x, p.y, p.reference_id)?;
        Ok(PositionXYC::with_ref(v.x, v.y, p.c, cs))
    }

    /// The same point in the local system of the named part (part at its current position,
    /// §1.3); `None` if the point lies in another coordinate system than the part.
    pub(crate) fn to_part_local(
        &self,
        p: &PositionXYC,
        part: &str,
    ) -> Result<Option<PositionXYC>, Rejection> {
        let cs_pos = self.resolve_position(p)?;
        let part = &self.parts[self.part(part)?];
        let (cs, o) = part.origin();
        Ok((cs == cs_pos.reference_id)
            .then(|| PositionXYC::with_ref(cs_pos.x - o.x, cs_pos.y - o.y, p.c, part.oid)))
    }

    pub(crate) fn new_id(&mut self) -> CmdId {
        let id = CmdId(self.next_id);
        self.next_id += 1;
        id
    }

    pub(crate) fn mover(&self, name: &str) -> Result<usize, Rejection> {
        self.mover_idx
            .get(name)
            .copied()
            .ok_or_else(|| Rejection::unknown_object("mover", name))
    }

    pub(crate) fn group(&self, name: &str) -> Result<usize, Rejection> {
        self.group_idx
            .get(name)
            .copied()
            .ok_or_else(|| Rejection::unknown_object("group", name))
    }

    pub(super) fn part(&self, name: &str) -> Result<usize, Rejection> {
        self.part_idx
            .get(name)
            .copied()
            .ok_or_else(|| Rejection::unknown_object("part", name))
    }

    // ------------------------------------------------------------------ coordinates (§1.3, §1.4)

    pub(super) fn parts_static(&self) -> bool {
        self.parts.iter().all(|p| p.positions.len() == 1)
    }

    /// Resolves (x, y, ReferenceId) to (CS, point in that CS).
    pub(crate) fn resolve(
        &self,
        who: &str,
        x: f64,
        y: f64,
        reference_id: u32,
    ) -> Result<(u32, V2), Rejection> {
        if reference_id == 0 {
            if self.coordinate_systems.len() == 1 && self.parts_static() {
                return Ok((self.coordinate_systems[0], V2::new(x, y)));
            }
            return Err(reject(
                E_INVALID_REFERENCE_ID,
                format!("{who}: ReferenceId 0 is only valid with one coordinate system and static parts"),
            ));
        }
        if self.coordinate_systems.contains(&reference_id) {
            return Ok((reference_id, V2::new(x, y)));
        }
        if let Some(p) = self.parts.iter().find(|p| p.oid == reference_id) {
            let (cs, o) = p.origin();
            return Ok((cs, o + V2::new(x, y)));
        }
        Err(reject(
            E_INVALID_REFERENCE_ID,
            format!(
                "{who}: ReferenceId 0x{reference_id:08X} is neither a coordinate system nor a part"
            ),
        ))
    }

    /// Stator tiles of a CS (parts at their current positions, else added stators); empty =
    /// unbounded plane.
    pub(crate) fn area_tiles(&self, cs: u32) -> Vec<V2> {
        if self.parts.is_empty() {
            return self.env.stators.clone();
        }
        let mut t = vec![];
        for p in &self.parts {
            let (pcs, o) = p.origin();
            if pcs == cs {
                t.extend(p.tiles.iter().map(|x| x + o));
            }
        }
        t
    }

    pub(crate) fn part_of(&self, m: &Mover) -> Option<usize> {
        let p = m.xy_out().pos;
        self.parts.iter().position(|part| part.contains(m.cs, p))
    }

    pub(super) fn check_in_area(&self, who: &str, cs: u32, p: V2) -> Result<(), Rejection> {
        let tiles = self.area_tiles(cs);
        if (!self.parts.is_empty() || !tiles.is_empty())
            && crate::geometry::tile_containing(&tiles, p).is_none()
        {
            return Err(reject(
                E_TARGET_UNREACHABLE,
                format!(
                    "{who}: target ({}, {}) is outside the stator area",
                    p.x, p.y
                ),
            ));
        }
        Ok(())
    }

    // ------------------------------------------------------------------ common checks

    pub(crate) fn require_enabled(&self, i: usize, what: &str) -> Result<(), Rejection> {
        let m = &self.movers[i];
        if m.sm.state != PlanarState::Enabled {
            return Err(reject(
                E_INVALID_STATE,
                format!(
                    "mover '{}': {what} requires state Enabled, is {:?}",
                    m.name, m.sm.state
                ),
            ));
        }
        Ok(())
    }

    pub(crate) fn require_mode(
        &self,
        i: usize,
        kind: CommandKind,
        what: &str,
    ) -> Result<(), Rejection> {
        let m = &self.movers[i];
        let ctx = AdmissionContext {
            standing: m.xy_standing(),
            esg_active: m.esg.is_some(),
        };
        if !admissible(kind, m.mode, ctx) {
            return Err(reject(
                E_INVALID_COMMAND_MODE,
                format!(
                    "mover '{}': {what} not allowed in command mode {:?}{}",
                    m.name,
                    m.mode,
                    if ctx.standing { "" } else { " while moving" }
                ),
            ));
        }
        Ok(())
    }

    pub(crate) fn require_group_ready(&self, i: usize) -> Result<(), Rejection> {
        if let Some(g) = self.movers[i].group {
            let g = &self.groups[g];
            if g.sm.state != PlanarState::Enabled {
                return Err(reject(
                    E_GROUP_NOT_READY,
                    format!(
                        "mover '{}': its group '{}' is {:?}",
                        self.movers[i].name, g.name, g.sm.state
                    ),
                ));
            }
        }
        Ok(())
    }

    pub(crate) fn require_part_still(&self, i: usize) -> Result<(), Rejection> {
        if let Some(p) = self.part_of(&self.movers[i]) {
            if self.parts[p].transit.is_some() {
                return Err(reject(
                    E_INVALID_STATE,
                    format!(
                        "mover '{}': its part '{}' is moving",
                        self.movers[i].name, self.parts[p].name
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Area a member currently reserves in its group (§5.11).
    pub(crate) fn reservation(&self, j: usize) -> ConvexPolygon {
        let m = &self.movers[j];
        match &m.reserved {
            Some(r) => *r,
            None => m.footprint(),
        }
    }

    /// E_COLLISION with mover `j` as the blocking object (`objectInfo`).
    pub(crate) fn mover_collision(&mut self, who: &str, j: usize) -> Rejection {
        let m = &self.movers[j];
        let info = PlanarObjectInfo {
            object_type: PlanarObjectType::Mover,
            id: m.oid,
        };
        let name = m.name.clone();
        self.collision(who, info, &name)
    }

    pub(crate) fn collision(&mut self, who: &str, info: PlanarObjectInfo, name: &str) -> Rejection {
        self.last_object_info = info;
        reject(
            E_COLLISION,
            format!(
                "{who}: area blocked by {:?} '{name}' (oid 0x{:08X})",
                info.object_type, info.id
            ),
        )
        .with_object(motion_core::ObjectRef {
            kind: info.object_type as u16,
            id: info.id,
        })
    }

    /// Group reservation check of a swept area (§5.11); without a group, the area must not
    /// run into a mover that stands idle (task: commands that would collide are refused).
    pub(crate) fn check_swept(
        &mut self,
        tracks: &mut dyn TrackHooks,
        i: usize,
        swept: &ConvexPolygon,
    ) -> Result<(), Rejection> {
        let who = format!("mover '{}'", self.movers[i].name);
        let cs = self.movers[i].cs;
        if let Some(g) = self.movers[i].group {
            for k in 0..self.groups[g].movers.len() {
                let j = self.groups[g].movers[k];
                if j != i && self.movers[j].cs == cs && swept.intersects(&self.reservation(j)) {
                    return Err(self.mover_collision(&who, j));
                }
            }
            if self.groups[g].environment {
                let tiles = self.area_tiles(cs);
                if !swept.inside_tiles(&tiles) {
                    let (oid, name) = (self.env.oid, self.env.name.clone());
                    return Err(self.collision(
                        &who,
                        PlanarObjectInfo {
                            object_type: PlanarObjectType::Environment,
                            id: oid,
                        },
                        &name,
                    ));
                }
            }
        }
        // Outside a group there are no collision checks (§3.2): the command is accepted, and
        // a contact on the way is a crash (see `crash`).
        let grouped = self.movers[i].group.is_some();
        for j in 0..self.movers.len() {
            let o = &self.movers[j];
            if !grouped || j == i || o.cs != cs || !o.at_rest() || o.xy_cmd.is_some() {
                continue;
            }
            if swept.intersects(&o.footprint()) {
                return Err(self.mover_collision(&who, j));
            }
        }
        // §5.11: Moving member tracks of the mover's group block their area.
        tracks.check_swept(self, i, swept)
    }

    /// Mover `m`'s snapshot, in `old`'s buffers.
    fn snapshot_mover(
        &self,
        tracks: &dyn TrackHooks,
        m: &Mover,
        old: MoverSnapshot,
    ) -> MoverSnapshot {
        let part = self.part_of(m);
        let o = &m.offset;
        let xy = m.xy_out();
        let busy_xyc = m.xy_cmd.is_some()
            || m.halt_cmd.is_some()
                && (m.path.is_some() || m.track.as_ref().is_some_and(|t| t.plan.is_some()))
            || m.esg
                .as_ref()
                .is_some_and(|e| e.mode == ExternalSetpointMode::Absolute);
        let busy = BusyFlags {
            busy_xyc,
            busy_c: m.c_cmd.is_some(),
            busy_z: m.z_cmd.is_some(),
            busy_a: m.a_cmd.is_some(),
            busy_b: m.b_cmd.is_some(),
            busy_mover: busy_xyc
                || m.c_cmd.is_some()
                || m.z_cmd.is_some()
                || m.a_cmd.is_some()
                || m.b_cmd.is_some()
                || m.halt_cmd.is_some()
                || m.esg.is_some(),
        };
        MoverSnapshot {
            name: reuse_str(old.name, &m.name),
            oid: m.oid,
            state: m.sm.state,
            command_mode: if m.sm.state == PlanarState::Enabled {
                m.mode
            } else {
                CommandMode::Invalid
            },
            busy,
            group_oid: m.group.map(|g| self.groups[g].oid).unwrap_or(0),
            group: reuse_opt_str(old.group, m.group.map(|g| self.groups[g].name.as_str())),
            part_oid: part.map(|p| self.parts[p].oid).unwrap_or(0),
            part: reuse_opt_str(old.part, part.map(|p| self.parts[p].name.as_str())),
            coordinate_system_oid: m.cs,
            error_id: m.sm.error_id,
            error_reaction: m.sm.reaction,
            external_setpoint_mode: m
                .esg
                .as_ref()
                .map(|e| e.mode)
                .unwrap_or(ExternalSetpointMode::None),
            warning_id: m.warning,
            object_info: m.object_info,
            set_pos: m.pose(),
            set_velo: MoverVector {
                x: xy.vel.x,
                y: xy.vel.y,
                z: m.z.vel + o.vel.z,
                a: m.a.vel + o.vel.a,
                b: m.b.vel + o.vel.b,
                c: m.c.vel + o.vel.c,
            },
            set_acc: MoverVector {
                x: xy.acc.x,
                y: xy.acc.y,
                z: m.z.acc + o.acc.z,
                a: m.a.acc + o.acc.a,
                b: m.b.acc + o.acc.b,
                c: m.c.acc + o.acc.c,
            },
            c_coordinate_mode: m.c_mode,
            active: ActiveCommands {
                xy: m.xy_cmd.or(m.halt_cmd),
                c: m.c_cmd,
                z: m.z_cmd,
                a: m.a_cmd,
                b: m.b_cmd,
                external_setpoint: m.esg.as_ref().map(|e| e.session),
            },
            on_track: tracks.mover_on_track(self, m, old.on_track),
            joining_or_leaving: reuse_opt_str(
                old.joining_or_leaving,
                m.joining
                    .map(|j| j.0)
                    .or(m.leaving)
                    .map(|k| tracks.track_name(k)),
            ),
        }
    }
}

impl Objects {
    /// The snapshot of the objects and the tracks, built in an older snapshot's buffers (a
    /// lockstep state stream takes one every cycle; nothing is allocated once they are warm).
    pub(crate) fn snapshot_into(&self, tracks: &dyn TrackHooks, out: &mut PlanarSnapshot) {
        let old = std::mem::take(out);
        let mut added_stators = old.environment.added_stators;
        added_stators.clear();
        added_stators.extend(self.env.stators.iter().map(|v| [v.x, v.y]));
        let (track_snapshots, axes) = tracks.snapshots(self, old.tracks, old.axes);
        *out = PlanarSnapshot {
            time: self.time,
            environment: EnvironmentSnapshot {
                name: reuse_str(old.environment.name, &self.env.name),
                oid: self.env.oid,
                group_oid: self.env.group.map(|g| self.groups[g].oid).unwrap_or(0),
                stator_count: if self.parts.is_empty() {
                    self.env.stators.len()
                } else {
                    self.parts.iter().map(|p| p.tiles.len()).sum()
                },
                boundary_element_count: self.env.boundary.unwrap_or(0),
                part_count: self.parts.len(),
                added_stators,
            },
            movers: refill_vec(old.movers, self.movers.len(), |i, old| {
                self.snapshot_mover(tracks, &self.movers[i], old)
            }),
            groups: refill_vec(old.groups, self.groups.len(), |gi, old| {
                let g = &self.groups[gi];
                let member_tracks = tracks.group_tracks(gi, old.tracks);
                GroupSnapshot {
                    name: reuse_str(old.name, &g.name),
                    oid: g.oid,
                    state: g.sm.state,
                    member_count: g.movers.len() + g.environment as usize + member_tracks.len(),
                    tracks: member_tracks,
                    movers: reuse_strs(
                        old.movers,
                        g.movers.iter().map(|&j| self.movers[j].name.as_str()),
                    ),
                    environment_member: g.environment,
                }
            }),
            parts: refill_vec(old.parts, self.parts.len(), |pi, old| {
                let p = &self.parts[pi];
                let (cs, o) = p.origin();
                PartSnapshot {
                    name: reuse_str(old.name, &p.name),
                    oid: p.oid,
                    state: p.sm.state,
                    position_index: p.index,
                    position: PositionXYC::with_ref(o.x, o.y, 0.0, cs),
                    disable_forced: p.force_disabled,
                    is_initialized: p.initialized,
                    moving: p.transit.is_some(),
                }
            }),
            tracks: track_snapshots,
            axes,
        };
    }

    /// A cancelled goal: the mover halts (MC_Halt semantics) or its ESG session stops.
    pub(crate) fn cancel(
        &mut self,
        tracks: &mut dyn TrackHooks,
        id: CmdId,
    ) -> Result<(), Rejection> {
        for i in 0..self.movers.len() {
            let m = &self.movers[i];
            if m.xy_cmd == Some(id)
                || m.c_cmd == Some(id)
                || m.z_cmd == Some(id)
                || m.a_cmd == Some(id)
                || m.b_cmd == Some(id)
            {
                let name = m.name.clone();
                return self
                    .dispatch(
                        tracks,
                        PlanarCommand::Halt {
                            mover: name,
                            constraint: DynamicConstraint::default(),
                        },
                    )
                    .map(|_| ());
            }
            if m.esg.as_ref().is_some_and(|e| e.session == id) {
                return self.stop_esg(i).map(|_| ());
            }
        }
        Ok(())
    }
}
