//! `PlanarEngine`: the object model, command admission and the cycle (xplanar.md §1–§3, §5).
//!
//! Commands are admitted at once (no queue, §2.4): a new command aborts the active command
//! of its axis domain. `step` advances parts, state machines and set points by one cycle;
//! the no-overlap guard ([`crate::guard`]) runs on every cycle.

use crate::admission::{admissible, AdmissionContext, CommandKind};
use crate::command::{ObjectKind, PlanarCommand};
use crate::config::PlanarConfig;
use crate::errors::*;
use crate::geometry::{boundary_elements, tiles_overlap, ConvexPolygon, V2};
use crate::guard::Grid;
use crate::motion::{
    in_c_window, modulo_target, range_in_one_window, stop_range, Axis1, Kin2, PathPlan,
};
use crate::objects::{Environment, Esg, Group, Mover, Part, Setpoint};
use crate::snapshot::*;
use crate::state::{Accepted, PlanarStateMachine, Timing};
use crate::types::*;
use motion_core::trajectory::State1;
use motion_core::{CmdId, CommandEvent, CommandState, Engine, ErrorId, Rejection, Tick};
use std::collections::HashMap;

/// The XPlanar engine (part 1: free movement, groups, parts; no tracks yet).
pub struct PlanarEngine {
    pub(crate) timing: Timing,
    pub(crate) cycle_time: f64,
    pub(crate) part_move_time: f64,
    pub(crate) esg_timeout_cycles: u32,
    pub(crate) time: f64,
    pub(crate) coordinate_systems: Vec<u32>,
    pub(crate) env: Environment,
    pub(crate) parts: Vec<Part>,
    pub(crate) movers: Vec<Mover>,
    pub(crate) groups: Vec<Group>,
    pub(crate) mover_idx: HashMap<String, usize>,
    pub(crate) group_idx: HashMap<String, usize>,
    pub(crate) part_idx: HashMap<String, usize>,
    pub(crate) next_id: u64,
    /// Status changes produced by `command`, reported in the next `step`.
    pub(crate) pending: Vec<CommandEvent>,
    pub(crate) grid: Grid,
    pub(crate) scratch: Vec<u32>,
    pub(crate) last_object_info: PlanarObjectInfo,
    /// Tracks in configuration order (§1.6).
    pub(crate) tracks: Vec<crate::track::Track>,
    pub(crate) track_idx: HashMap<String, usize>,
    /// False while every mover is on one track (the guard grid is skipped, see step_motion).
    pub(crate) guard_full: bool,
    /// Switches of the track network (§5.6.4), rebuilt after geometry and link changes.
    pub(crate) switches: Vec<crate::track::Switch>,
    /// Virtual master axes (§5.8.4).
    pub(crate) axes: Vec<crate::track::VirtualAxis>,
    pub(crate) axis_idx: HashMap<String, usize>,
}

pub(crate) fn ev(events: &mut Vec<CommandEvent>, id: CmdId, state: CommandState) {
    events.push(CommandEvent { id, state });
}

pub(crate) fn end(events: &mut Vec<CommandEvent>, slot: &mut Option<CmdId>, state: CommandState) {
    if let Some(id) = slot.take() {
        ev(events, id, state);
    }
}

pub(crate) fn traj_err(who: &str, e: motion_core::trajectory::TrajectoryError) -> Rejection {
    reject(E_INVALID_PARAMETER, format!("{who}: {e}"))
}

impl PlanarEngine {
    /// The objects of `cfg` (environment, parts, movers, groups, tracks without their init
    /// parameters, virtual axes); [`PlanarEngine::new`] (build.rs) adds the tracks' init.
    pub(crate) fn with_objects(cfg: &PlanarConfig) -> Result<Self, Rejection> {
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
        let part_frames: Vec<crate::track::PartFrame> = parts
            .iter()
            .map(|p| {
                let (cs, origin) = p.origin();
                crate::track::PartFrame {
                    oid: p.oid,
                    cs,
                    origin,
                }
            })
            .collect();
        let (tracks, track_idx) = crate::track::build_tracks(cfg, &part_frames);
        let (axes, axis_idx) = crate::track::build_axes(cfg);
        let part_idx = parts
            .iter()
            .enumerate()
            .map(|(i, p)| (p.name.clone(), i))
            .collect();
        let eng = PlanarEngine {
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
            tracks,
            track_idx,
            axes,
            axis_idx,
            switches: Vec::new(),
            guard_full: true,
        };
        Ok(eng)
    }

    /// The configured cycle time \[s\].
    pub fn cycle_time(&self) -> f64 {
        self.cycle_time
    }

    /// `objectInfo` of the last E_COLLISION (rejection or guard stop): the blocking object (§6.1).
    pub fn last_object_info(&self) -> PlanarObjectInfo {
        self.last_object_info
    }

    /// Converts a position with ReferenceId (CS OID, part OID or 0) into its coordinate
    /// system (§1.3, §1.4); the result's `reference_id` is the CS OID.
    pub fn resolve_position(&self, p: &PositionXYC) -> Result<PositionXYC, Rejection> {
        p.check_finite("resolve_position", "position")?;
        let (cs, v) = self.resolve("resolve_position", p.x, p.y, p.reference_id)?;
        Ok(PositionXYC::with_ref(v.x, v.y, p.c, cs))
    }

    /// The same point in the local system of the named part (part at its current position,
    /// §1.3); `None` if the point lies in another coordinate system than the part.
    pub fn to_part_local(
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

    fn group(&self, name: &str) -> Result<usize, Rejection> {
        self.group_idx
            .get(name)
            .copied()
            .ok_or_else(|| Rejection::unknown_object("group", name))
    }

    fn part(&self, name: &str) -> Result<usize, Rejection> {
        self.part_idx
            .get(name)
            .copied()
            .ok_or_else(|| Rejection::unknown_object("part", name))
    }

    // ------------------------------------------------------------------ coordinates (§1.3, §1.4)

    fn parts_static(&self) -> bool {
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

    fn check_in_area(&self, who: &str, cs: u32, p: V2) -> Result<(), Rejection> {
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
    pub(crate) fn check_swept(&mut self, i: usize, swept: &ConvexPolygon) -> Result<(), Rejection> {
        let who = format!("mover '{}'", self.movers[i].name);
        let cs = self.movers[i].cs;
        if let Some(g) = self.movers[i].group {
            for k in 0..self.groups[g].movers.len() {
                let j = self.groups[g].movers[k];
                if j != i && self.movers[j].cs == cs && swept.intersects(&self.reservation(j)) {
                    let (oid, name) = (self.movers[j].oid, self.movers[j].name.clone());
                    return Err(self.collision(
                        &who,
                        PlanarObjectInfo {
                            object_type: PlanarObjectType::Mover,
                            id: oid,
                        },
                        &name,
                    ));
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
                let (oid, name) = (o.oid, o.name.clone());
                return Err(self.collision(
                    &who,
                    PlanarObjectInfo {
                        object_type: PlanarObjectType::Mover,
                        id: oid,
                    },
                    &name,
                ));
            }
        }
        // §5.11: Moving member tracks of the mover's group block their area.
        self.check_moving_tracks(i, swept)
    }

    // ------------------------------------------------------------------ mover commands (§3.2)

    pub(crate) fn move_to_position(
        &mut self,
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
        let (dxy, red1) = Dynamics::resolve(
            &m.cfg.default_dynamics,
            &m.cfg.max_dynamics,
            &constraint,
            &who,
            "constraint",
        )?;
        let (dc, _) = Dynamics::resolve(
            &m.cfg.c_default_dynamics,
            &m.cfg.c_max_dynamics,
            &DynamicConstraint::default(),
            &who,
            "constraint",
        )?;
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
        self.check_swept(i, &swept)?;
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
        m.warning = if red1 {
            W_DYNAMICS_REDUCED
        } else {
            ErrorId::NONE
        };
        ev(ev_, id, CommandState::Active);
        Ok(PlanarReply {
            id,
            warning_id: m.warning,
            value: ReplyValue::None,
        })
    }

    pub(crate) fn move_c(
        &mut self,
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
        let (dc, red) = Dynamics::resolve(
            &m.cfg.c_default_dynamics,
            &m.cfg.c_max_dynamics,
            &constraint,
            &who,
            "constraint",
        )?;
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
            self.check_swept(i, &swept)?;
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
        m.warning = if red {
            W_DYNAMICS_REDUCED
        } else {
            ErrorId::NONE
        };
        ev(ev_, id, CommandState::Active);
        Ok(PlanarReply {
            id,
            warning_id: m.warning,
            value: ReplyValue::None,
        })
    }

    fn move_aux(
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
        let (d, red) = Dynamics::resolve(
            &m.cfg.aux_default_dynamics,
            &m.cfg.aux_max_dynamics,
            &constraint,
            &who,
            "constraint",
        )?;
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
        m.warning = if red {
            W_DYNAMICS_REDUCED
        } else {
            ErrorId::NONE
        };
        ev(ev_, id, CommandState::Active);
        Ok(PlanarReply {
            id,
            warning_id: m.warning,
            value: ReplyValue::None,
        })
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
        let (dxy, _) = Dynamics::resolve(
            &m.cfg.default_dynamics,
            &m.cfg.max_dynamics,
            &constraint,
            &who,
            "constraint",
        )?;
        let (dc, _) = Dynamics::resolve(
            &m.cfg.c_default_dynamics,
            &m.cfg.c_max_dynamics,
            &DynamicConstraint::default(),
            &who,
            "constraint",
        )?;
        let (da, _) = Dynamics::resolve(
            &m.cfg.aux_default_dynamics,
            &m.cfg.aux_max_dynamics,
            &DynamicConstraint::default(),
            &who,
            "constraint",
        )?;
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

    fn enable_mover(&mut self, i: usize) -> Result<PlanarReply, Rejection> {
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

    fn disable_mover(&mut self, i: usize) -> Result<PlanarReply, Rejection> {
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

    fn reset_mover(&mut self, i: usize) -> Result<PlanarReply, Rejection> {
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

    fn set_position(&mut self, i: usize, pos: PositionXYC) -> Result<PlanarReply, Rejection> {
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
                let (oid, name) = (self.movers[j].oid, self.movers[j].name.clone());
                return Err(self.collision(
                    &who,
                    PlanarObjectInfo {
                        object_type: PlanarObjectType::Mover,
                        id: oid,
                    },
                    &name,
                ));
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

    fn start_esg(
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

    fn stop_esg(&mut self, i: usize) -> Result<PlanarReply, Rejection> {
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

    fn set_external_setpoint(
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

    fn mover_add_to_group(&mut self, i: usize, gname: &str) -> Result<PlanarReply, Rejection> {
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
                let (oid, name) = (self.movers[j].oid, self.movers[j].name.clone());
                return Err(self.collision(
                    &who,
                    PlanarObjectInfo {
                        object_type: PlanarObjectType::Mover,
                        id: oid,
                    },
                    &name,
                ));
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

    fn mover_remove_from_group(&mut self, i: usize) -> Result<PlanarReply, Rejection> {
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

    fn position_on_current_part(&mut self, i: usize) -> Result<PlanarReply, Rejection> {
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

    // ------------------------------------------------------------------ environment (§3.1)

    fn env_add_stator(&mut self, x: f64, y: f64) -> Result<PlanarReply, Rejection> {
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

    fn env_tiles_for_boundary(&self) -> Vec<V2> {
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

    fn part_initialized(&self, p: usize) -> Result<(), Rejection> {
        if !self.parts[p].initialized {
            return Err(reject(
                E_PART_NOT_INITIALIZED,
                format!("part '{}': Initialize first", self.parts[p].name),
            ));
        }
        Ok(())
    }

    fn activate_position(&mut self, p: usize, index: u32) -> Result<PlanarReply, Rejection> {
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
                    let (oid, name) = (o.oid, o.name.clone());
                    return Err(self.collision(
                        &who,
                        PlanarObjectInfo {
                            object_type: PlanarObjectType::Mover,
                            id: oid,
                        },
                        &name,
                    ));
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
    fn holds_parts(m: &Mover) -> bool {
        match m.sm.state {
            PlanarState::Enabling | PlanarState::Enabled | PlanarState::Disabling => true,
            PlanarState::ErrorPending | PlanarState::Error | PlanarState::Resetting => {
                m.sm.reaction == ErrorReaction::QuickStop
            }
            _ => false,
        }
    }

    /// A part is enabled iff its CS holds an enabled mover and it is not force-disabled (§2.6).
    fn reconcile_parts(&mut self) {
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

    fn mover_error(&mut self, i: usize, id: ErrorId, reaction: ErrorReaction) {
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

    // ------------------------------------------------------------------ the cycle

    fn step_parts(&mut self, dt: f64) {
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
                for t in self.tracks.iter_mut().filter(|t| t.part_oid == part_oid) {
                    t.cs = cs_new;
                }
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

    fn step_states(&mut self, dt: f64) {
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
                        self.detach_from_track(i);
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

    /// Envelope of a mover state: footprint swept along its maximum-dynamics stop (§5.11 guard).
    pub(crate) fn envelope_of(m: &Mover, xy: &Kin2, c: &State1) -> ConvexPolygon {
        let c_moves = c.vel != 0.0 || c.acc != 0.0;
        let fp = if c_moves {
            let h = m.diag() / 2.0;
            ConvexPolygon::aabb_box(V2::new(-h, -h), V2::new(h, h))
        } else {
            ConvexPolygon::rect(V2::zeros(), m.cfg.width, m.cfg.height, c.pos)
        };
        if !xy.moving() {
            return if c_moves {
                m.square_at(xy.pos)
            } else {
                ConvexPolygon::rect(xy.pos, m.cfg.width, m.cfg.height, c.pos)
            };
        }
        let u = if xy.vel.norm() > 1e-12 {
            xy.vel.normalize()
        } else {
            xy.acc.normalize()
        };
        let n = V2::new(-u.y, u.x);
        let (d, j) = (m.cfg.max_dynamics.deceleration, m.cfg.max_dynamics.jerk);
        let (s0, s1) = stop_range(xy.vel.dot(&u), xy.acc.dot(&u), d, j);
        let (q0, q1) = stop_range(xy.vel.dot(&n), xy.acc.dot(&n), d, j);
        let bx = ConvexPolygon::hull(&[
            xy.pos + u * s0 + n * q0,
            xy.pos + u * s1 + n * q0,
            xy.pos + u * s1 + n * q1,
            xy.pos + u * s0 + n * q1,
        ]);
        bx.minkowski(&fp)
    }

    fn step_motion(&mut self, dt: f64) {
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
            self.step_mover(i, dt, &mut grid, &mut cand);
        }
        self.grid = grid;
        self.scratch = cand;
    }

    fn esg_check(m: &Mover, sp: &Setpoint, dt: f64) -> Option<(ErrorId, String)> {
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

    fn step_mover(&mut self, i: usize, dt: f64, grid: &mut Grid, cand: &mut Vec<u32>) {
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
            self.step_track_mover(i, dt, grid, cand);
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
            self.finish_idle(i);
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
            let env = Self::envelope_of(m, &shown, &c_shown);
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
                self.advance_committed(i, dt);
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
        self.finish_idle(i);
    }

    /// Stops mover `i` at the last pose on its way to the next set point (`xy_next`,
    /// `c_next`, internal coordinates) where `blocked` (centre and C as shown) is still false,
    /// found by bisection: a physical stop at a contact, never past it.
    fn stop_at_contact(
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
    fn crash(&mut self, i: usize, j: usize, xy_next: V2, c_next: f64) {
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
    fn on_stators(&self, cs: u32, p: V2) -> bool {
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
    fn fall_off(&mut self, i: usize, xy_next: V2, c_next: f64) {
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
    fn advance_committed(&mut self, i: usize, dt: f64) {
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
        self.finish_idle(i);
    }

    /// Bookkeeping once axes come to rest: Halt/Stop done, CRotation exit, reservation release.
    pub(crate) fn finish_idle(&mut self, i: usize) {
        self.track_finish_idle(i);
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

    fn snapshot_mover(&self, m: &Mover) -> MoverSnapshot {
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
            name: m.name.clone(),
            oid: m.oid,
            state: m.sm.state,
            command_mode: if m.sm.state == PlanarState::Enabled {
                m.mode
            } else {
                CommandMode::Invalid
            },
            busy,
            group_oid: m.group.map(|g| self.groups[g].oid).unwrap_or(0),
            group: m.group.map(|g| self.groups[g].name.clone()),
            part_oid: part.map(|p| self.parts[p].oid).unwrap_or(0),
            part: part.map(|p| self.parts[p].name.clone()),
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
            on_track: self.on_track_snapshot(m),
            joining_or_leaving: m
                .joining
                .map(|j| j.0)
                .or(m.leaving)
                .map(|k| self.tracks[k].name.clone()),
        }
    }

    fn dispatch(&mut self, cmd: PlanarCommand) -> Result<PlanarReply, Rejection> {
        use PlanarCommand as C;
        match cmd {
            C::EnvironmentClear => {
                if self.env.group.is_some() {
                    return Err(reject(
                        E_INVALID_STATE,
                        format!("environment '{}' is a group member", self.env.name),
                    ));
                }
                self.env.stators.clear();
                self.env.boundary = None;
                self.done_now()
            }
            C::AddStator { lower_x, lower_y } => self.env_add_stator(lower_x, lower_y),
            C::CreateBoundary => {
                let tiles = self.env_tiles_for_boundary();
                if tiles.is_empty() {
                    return Err(reject(
                        E_INVALID_PARAMETER,
                        format!("environment '{}': no stators", self.env.name),
                    ));
                }
                self.env.boundary = Some(boundary_elements(&tiles));
                self.done_now()
            }
            C::EnvironmentAddToGroup { group } => {
                let g = self.group(&group)?;
                if self.groups[g].sm.state != PlanarState::Enabled {
                    return Err(reject(
                        E_GROUP_NOT_READY,
                        format!(
                            "environment: group '{group}' is {:?}",
                            self.groups[g].sm.state
                        ),
                    ));
                }
                if self.env.boundary.is_none() && self.parts.is_empty() {
                    return Err(reject(E_INVALID_STATE, "environment: CreateBoundary first"));
                }
                if let Some(og) = self.env.group {
                    return Err(reject(
                        E_GROUP_NOT_READY,
                        format!(
                            "environment: already member of group '{}'",
                            self.groups[og].name
                        ),
                    ));
                }
                self.env.group = Some(g);
                self.groups[g].environment = true;
                self.done_now()
            }
            C::EnvironmentRemoveFromGroup => {
                if let Some(g) = self.env.group.take() {
                    self.groups[g].environment = false;
                }
                self.done_now()
            }
            C::EnvironmentGetPlanarObjectInfo => {
                let id = self.new_id();
                ev(&mut self.pending, id, CommandState::Done);
                Ok(PlanarReply {
                    id,
                    warning_id: ErrorId::NONE,
                    value: ReplyValue::ObjectInfo(PlanarObjectInfo {
                        object_type: PlanarObjectType::Environment,
                        id: self.env.oid,
                    }),
                })
            }
            C::MoveToPosition {
                mover,
                target_position,
                constraint,
                options,
            } => {
                let i = self.mover(&mover)?;
                self.move_to_position(i, target_position, constraint, options)
            }
            C::MoveZ {
                mover,
                target_position,
                constraint,
            } => {
                let i = self.mover(&mover)?;
                self.move_aux(i, 0, target_position, constraint)
            }
            C::MoveA {
                mover,
                target_position,
                constraint,
            } => {
                let i = self.mover(&mover)?;
                self.move_aux(i, 1, target_position, constraint)
            }
            C::MoveB {
                mover,
                target_position,
                constraint,
            } => {
                let i = self.mover(&mover)?;
                self.move_aux(i, 2, target_position, constraint)
            }
            C::MoveC {
                mover,
                target_position,
                constraint,
                options,
            } => {
                let i = self.mover(&mover)?;
                self.move_c(i, target_position, constraint, options)
            }
            C::Halt { mover, constraint } => {
                let i = self.mover(&mover)?;
                self.halt(i, constraint)
            }
            C::MoverEnable { mover } => {
                let i = self.mover(&mover)?;
                self.enable_mover(i)
            }
            C::MoverDisable { mover } => {
                let i = self.mover(&mover)?;
                self.disable_mover(i)
            }
            C::MoverReset { mover } => {
                let i = self.mover(&mover)?;
                self.reset_mover(i)
            }
            C::SetPosition { mover, position } => {
                let i = self.mover(&mover)?;
                self.set_position(i, position)
            }
            C::StartExternalSetpointGeneration { mover, options } => {
                let i = self.mover(&mover)?;
                self.start_esg(i, options)
            }
            C::StopExternalSetpointGeneration { mover } => {
                let i = self.mover(&mover)?;
                self.stop_esg(i)
            }
            C::SetExternalSetpoint {
                mover,
                set_position,
                set_velocity,
                set_acceleration,
            } => {
                let i = self.mover(&mover)?;
                self.set_external_setpoint(
                    i,
                    Setpoint {
                        pos: set_position,
                        vel: set_velocity,
                        acc: set_acceleration,
                    },
                    None,
                )
            }
            C::SetExternalSetpointReferenceId {
                mover,
                set_position,
                set_velocity,
                set_acceleration,
                reference_system_oid,
            } => {
                let i = self.mover(&mover)?;
                self.set_external_setpoint(
                    i,
                    Setpoint {
                        pos: set_position,
                        vel: set_velocity,
                        acc: set_acceleration,
                    },
                    Some(reference_system_oid),
                )
            }
            C::MoverAddToGroup { mover, group } => {
                let i = self.mover(&mover)?;
                self.mover_add_to_group(i, &group)
            }
            C::MoverRemoveFromGroup { mover } => {
                let i = self.mover(&mover)?;
                self.mover_remove_from_group(i)
            }
            C::GetPositionOnCurrentPart { mover } => {
                let i = self.mover(&mover)?;
                self.position_on_current_part(i)
            }
            C::MoverGetPlanarObjectInfo { mover } => {
                let i = self.mover(&mover)?;
                let id = self.new_id();
                ev(&mut self.pending, id, CommandState::Done);
                Ok(PlanarReply {
                    id,
                    warning_id: ErrorId::NONE,
                    value: ReplyValue::ObjectInfo(PlanarObjectInfo {
                        object_type: PlanarObjectType::Mover,
                        id: self.movers[i].oid,
                    }),
                })
            }
            C::GroupEnable { group } => {
                let g = self.group(&group)?;
                let id = self.new_id();
                let t = self.timing;
                let r = self.groups[g].sm.enable(
                    id,
                    &t,
                    &format!("group '{group}'"),
                    &mut self.pending,
                )?;
                ev(
                    &mut self.pending,
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
            C::GroupDisable { group } => {
                let g = self.group(&group)?;
                if let Some(&j) = self.groups[g]
                    .movers
                    .iter()
                    .find(|&&j| !self.movers[j].xy_standing() || self.movers[j].c.moving())
                {
                    return Err(reject(
                        E_INVALID_STATE,
                        format!(
                            "group '{group}': member '{}' is moving",
                            self.movers[j].name
                        ),
                    ));
                }
                let id = self.new_id();
                let t = self.timing;
                let r = self.groups[g].sm.disable(id, &t, &mut self.pending);
                ev(
                    &mut self.pending,
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
            C::GroupReset { group } => {
                let g = self.group(&group)?;
                let id = self.new_id();
                let t = self.timing;
                let r = self.groups[g]
                    .sm
                    .reset(id, &t, &format!("group '{group}'"))?;
                ev(
                    &mut self.pending,
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
            C::PartInitialize { part, part_oid } => {
                let p = self.part(&part)?;
                if self.parts[p].oid != part_oid {
                    return Err(reject(
                        E_INVALID_PART,
                        format!(
                            "part '{part}': part_oid = 0x{part_oid:08X} is not its OID 0x{:08X}",
                            self.parts[p].oid
                        ),
                    ));
                }
                self.parts[p].initialized = true;
                self.done_now()
            }
            C::ActivatePosition {
                part,
                position_index,
            } => {
                let p = self.part(&part)?;
                self.activate_position(p, position_index)
            }
            C::AllowEnable { part } => {
                let p = self.part(&part)?;
                self.part_initialized(p)?;
                self.parts[p].force_disabled = false;
                self.reconcile_parts();
                self.done_now()
            }
            C::ForceDisable { part } => {
                let p = self.part(&part)?;
                self.part_initialized(p)?;
                self.parts[p].force_disabled = true;
                for i in 0..self.movers.len() {
                    if self.parts[p].contains(self.movers[i].cs, self.movers[i].xy_out().pos)
                        && Self::holds_parts(&self.movers[i])
                    {
                        self.mover_error(i, E_PART_DISABLED, ErrorReaction::Abort);
                    }
                }
                self.reconcile_parts();
                self.done_now()
            }
            C::PartReset { part } => {
                let p = self.part(&part)?;
                self.part_initialized(p)?;
                let id = self.new_id();
                let t = self.timing;
                let r = self.parts[p].sm.reset(id, &t, &format!("part '{part}'"))?;
                ev(
                    &mut self.pending,
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
            C::PartGetPosition { part } => {
                let p = self.part(&part)?;
                self.part_initialized(p)?;
                let (cs, o) = self.parts[p].origin();
                let id = self.new_id();
                ev(&mut self.pending, id, CommandState::Done);
                Ok(PlanarReply {
                    id,
                    warning_id: ErrorId::NONE,
                    value: ReplyValue::Position(PositionXYC::with_ref(o.x, o.y, 0.0, cs)),
                })
            }
            C::InjectError {
                kind,
                name,
                reaction,
            } => {
                if reaction == ErrorReaction::None {
                    return Err(reject(
                        ErrorId::ENUM_OUT_OF_RANGE,
                        format!("InjectError '{name}': reaction None"),
                    ));
                }
                let t = self.timing;
                match kind {
                    ObjectKind::Mover => {
                        let i = self.mover(&name)?;
                        self.mover_error(i, E_OBJECT_ERROR, reaction);
                    }
                    ObjectKind::Group => {
                        let g = self.group(&name)?;
                        self.groups[g]
                            .sm
                            .error(E_OBJECT_ERROR, reaction, &t, &mut self.pending);
                    }
                    ObjectKind::Part => {
                        let p = self.part(&name)?;
                        // §2.6: the movers on the part fail first (QuickStop), then the part.
                        for i in 0..self.movers.len() {
                            if self.parts[p]
                                .contains(self.movers[i].cs, self.movers[i].xy_out().pos)
                            {
                                self.mover_error(i, E_PART_DISABLED, ErrorReaction::QuickStop);
                            }
                        }
                        self.parts[p]
                            .sm
                            .error(E_OBJECT_ERROR, reaction, &t, &mut self.pending);
                    }
                    ObjectKind::Track => {
                        let k = self.track(&name)?;
                        self.tracks[k]
                            .sm
                            .error(E_OBJECT_ERROR, reaction, &t, &mut self.pending);
                    }
                }
                self.done_now()
            }
            // Tracks and the on-track mover methods (§3.2, §3.3): crate::track.
            cmd => self.track_command(cmd),
        }
    }
}

impl Engine for PlanarEngine {
    type Command = PlanarCommand;
    type Reply = PlanarReply;
    type Snapshot = PlanarSnapshot;

    fn command(&mut self, cmd: PlanarCommand) -> Result<PlanarReply, Rejection> {
        self.last_object_info = PlanarObjectInfo::default();
        self.dispatch(cmd)
    }

    /// `Halt(fb)` of every mover with its default deceleration and jerk (§4.7); a mover that
    /// cannot take it (not enabled, in error) is left as it is.
    fn fail_safe_stop(&mut self) {
        for i in 0..self.movers.len() {
            let mover = self.movers[i].name.clone();
            let _ = self.command(PlanarCommand::Halt {
                mover,
                constraint: crate::types::DynamicConstraint::default(),
            });
        }
    }

    fn at_rest(&self) -> bool {
        self.snapshot()
            .movers
            .iter()
            .all(|m| m.set_velo.to_array().iter().all(|v| *v == 0.0))
    }

    fn step(&mut self, tick: Tick, events: &mut Vec<CommandEvent>) {
        let dt = tick.dt;
        self.step_parts(dt);
        self.step_states(dt);
        self.step_tracks(dt);
        self.step_axes(dt);
        self.step_motion(dt);
        self.time += dt;
        events.append(&mut self.pending);
    }

    fn snapshot(&self) -> PlanarSnapshot {
        PlanarSnapshot {
            time: self.time,
            environment: EnvironmentSnapshot {
                name: self.env.name.clone(),
                oid: self.env.oid,
                group_oid: self.env.group.map(|g| self.groups[g].oid).unwrap_or(0),
                stator_count: if self.parts.is_empty() {
                    self.env.stators.len()
                } else {
                    self.parts.iter().map(|p| p.tiles.len()).sum()
                },
                boundary_element_count: self.env.boundary.unwrap_or(0),
                part_count: self.parts.len(),
                added_stators: self.env.stators.iter().map(|v| [v.x, v.y]).collect(),
            },
            movers: self.movers.iter().map(|m| self.snapshot_mover(m)).collect(),
            groups: self
                .groups
                .iter()
                .enumerate()
                .map(|(gi, g)| GroupSnapshot {
                    name: g.name.clone(),
                    oid: g.oid,
                    state: g.sm.state,
                    member_count: g.movers.len()
                        + g.environment as usize
                        + self.tracks.iter().filter(|t| t.group == Some(gi)).count(),
                    tracks: self
                        .tracks
                        .iter()
                        .filter(|t| t.group == Some(gi))
                        .map(|t| t.name.clone())
                        .collect(),
                    movers: g
                        .movers
                        .iter()
                        .map(|&j| self.movers[j].name.clone())
                        .collect(),
                    environment_member: g.environment,
                })
                .collect(),
            parts: self
                .parts
                .iter()
                .map(|p| {
                    let (cs, o) = p.origin();
                    PartSnapshot {
                        name: p.name.clone(),
                        oid: p.oid,
                        state: p.sm.state,
                        position_index: p.index,
                        position: PositionXYC::with_ref(o.x, o.y, 0.0, cs),
                        disable_forced: p.force_disabled,
                        is_initialized: p.initialized,
                        moving: p.transit.is_some(),
                    }
                })
                .collect(),
            tracks: self.track_snapshots(),
            axes: self.axis_snapshots(),
        }
    }

    /// Every accepted command has an id whose events follow (instant ones end Done at once).
    fn reply_id(reply: &PlanarReply) -> Option<CmdId> {
        Some(reply.id)
    }

    fn error_text(id: ErrorId) -> String {
        error_name(id).to_string()
    }

    fn cancel(&mut self, id: CmdId) -> Result<(), Rejection> {
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
                    .dispatch(PlanarCommand::Halt {
                        mover: name,
                        constraint: DynamicConstraint::default(),
                    })
                    .map(|_| ());
            }
            if m.esg.as_ref().is_some_and(|e| e.session == id) {
                return self.stop_esg(i).map(|_| ());
            }
        }
        Ok(())
    }
}
