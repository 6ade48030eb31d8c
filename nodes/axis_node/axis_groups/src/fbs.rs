//! Part 4 FB semantics: screening, admission, the path jobs and their cycle, on the axes a
//! [`GroupCx`] gives them.

use super::*;
use crate::ids::*;
use motion_core::State1;
use single_axis::axis::{Job, JobKind};
use single_axis::error_ids::SOFT_LIMIT_TARGET;
use single_axis::inputs::BufferMode;

fn reject(id: ErrorId, msg: String) -> Rejection {
    Rejection::new(id, msg)
}

fn finite(group: &str, fb: &str, field: &str, v: f64) -> Result<(), Rejection> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(Rejection::not_finite(
            &format!("group '{group}': {fb}"),
            field,
            v,
        ))
    }
}

fn invalid(group: &str, fb: &str, msg: String) -> Rejection {
    reject(
        ERR_SIM_INVALID_PARAMETER,
        format!("group '{group}': {fb}: {msg}"),
    )
}

/// Dynamics screening: finite, Velocity > 0 (when given), the rest ≥ 0 (0 = members' limit).
fn dynamics(group: &str, fb: &str, velocity: Option<f64>, d: &Dyn) -> Result<(), Rejection> {
    if let Some(v) = velocity {
        finite(group, fb, "Velocity", v)?;
    }
    for (f, x) in [
        ("Acceleration", d.acceleration),
        ("Deceleration", d.deceleration),
        ("Jerk", d.jerk),
    ] {
        finite(group, fb, f, x)?;
    }
    if let Some(v) = velocity {
        if v <= 0.0 {
            return Err(invalid(group, fb, format!("Velocity = {v} must be > 0")));
        }
    }
    for (f, x) in [
        ("Acceleration", d.acceleration),
        ("Deceleration", d.deceleration),
        ("Jerk", d.jerk),
    ] {
        if x < 0.0 {
            return Err(invalid(
                group,
                fb,
                format!("{f} = {x} must be >= 0 (0 = the members' limit)"),
            ));
        }
    }
    Ok(())
}

fn only_aborting(group: &str, fb: &str, m: BufferMode) -> Result<(), Rejection> {
    if m == BufferMode::Aborting {
        Ok(())
    } else {
        Err(reject(
            ERR_SIM_NOT_IMPLEMENTED,
            format!(
                "group '{group}': {fb}: BufferMode {m:?} is not implemented (only MC_Aborting)"
            ),
        ))
    }
}

const V_REST: f64 = 1e-9;

impl GroupCx<'_> {
    fn group_index(&self, name: &str) -> Result<usize, Rejection> {
        self.groups.index_of(name)
    }

    fn group_untracked(&mut self, value: GroupReply) -> GroupCallReply {
        GroupCallReply {
            id: self.fbs.untracked_id(),
            value: Some(value),
            tracked: false,
        }
    }

    fn group_admit(
        &self,
        g: usize,
        fb: GroupFbClass,
        name: &str,
    ) -> Result<GroupAdmission, Rejection> {
        let grp = &self.groups.list[g];
        let state = grp.state(self.axes);
        match group_admission(fb, state) {
            GroupAdmission::Reject(id) => Err(reject(
                id,
                format!(
                    "group '{}': {name} not allowed in state {state:?}",
                    grp.name
                ),
            )),
            ok => Ok(ok),
        }
    }

    /// A new tracked group instance.
    fn group_instance(&mut self, g: usize, kind: GroupFbKind, state: CommandState) -> CmdId {
        let id = self.fbs.untracked_id();
        if self.groups.instances.len() > 4096 {
            let cycle = self.fbs.cycle;
            self.groups.instances.retain(|_, i| {
                !(i.state.is_final() && (!i.execute || i.ended_cycle + 1000 < cycle))
            });
        }
        self.groups.instances.insert(
            id,
            GroupInstance {
                group: g,
                kind,
                state,
                execute: true,
                ended_cycle: 0,
                cleared: false,
            },
        );
        // The admission is the instance's first status, reported like the later ones.
        if !state.is_final() {
            self.fbs
                .events
                .push(motion_core::CommandEvent { id, state });
        }
        id
    }

    fn group_tracked(id: CmdId) -> GroupCallReply {
        GroupCallReply {
            id,
            value: None,
            tracked: true,
        }
    }

    /// An administrative FB: applied at once, Done in the next cycle.
    fn group_admin_done(&mut self, g: usize) -> GroupCallReply {
        let id = self.group_instance(g, GroupFbKind::Administrative, CommandState::Busy);
        self.groups.instant_done.push(id);
        Self::group_tracked(id)
    }

    /// Member axis indices in IdentInGroup order.
    fn members(&self, g: usize) -> Vec<usize> {
        self.groups.list[g].axes().collect()
    }

    /// Set positions of the members.
    fn member_set(&self, g: usize) -> Vec<f64> {
        self.groups.list[g]
            .axes()
            .map(|i| self.axes[i].set.pos)
            .collect()
    }

    /// One Part 4 FB call.
    pub fn group_command(&mut self, cmd: GroupCommand) -> Result<GroupCallReply, Rejection> {
        let g = self.group_index(cmd.group())?;
        let gname = self.groups.list[g].name.clone();
        match cmd {
            GroupCommand::AddAxisToGroup(c) => {
                let fb = "MC_AddAxisToGroup";
                let ax = self
                    .index
                    .get(&c.axis)
                    .copied()
                    .ok_or_else(|| Rejection::unknown_object("axis", &c.axis))?;
                if let Some(other) = self.groups.of_axis[ax] {
                    let on = &self.groups.list[other].name;
                    return Err(invalid(
                        &gname,
                        fb,
                        format!("axis '{}' is already in group '{on}'", c.axis),
                    ));
                }
                let grp = &self.groups.list[g];
                let ident = if c.ident_in_group == 0 {
                    grp.members.iter().map(|m| m.0).max().unwrap_or(0) + 1
                } else {
                    c.ident_in_group
                };
                if grp.members.iter().any(|m| m.0 == ident) {
                    return Err(invalid(
                        &gname,
                        fb,
                        format!("IdentInGroup = {ident} is already used"),
                    ));
                }
                self.group_admit(g, GroupFbClass::Membership, fb)?;
                let grp = &mut self.groups.list[g];
                grp.members.push((ident, ax));
                grp.members.sort_unstable();
                grp.path.clear();
                self.groups.of_axis[ax] = Some(g);
                Ok(self.group_admin_done(g))
            }
            GroupCommand::RemoveAxisFromGroup(c) => {
                let fb = "MC_RemoveAxisFromGroup";
                let ax = self
                    .index
                    .get(&c.axis)
                    .copied()
                    .ok_or_else(|| Rejection::unknown_object("axis", &c.axis))?;
                if self.groups.of_axis[ax] != Some(g) {
                    return Err(invalid(
                        &gname,
                        fb,
                        format!("axis '{}' is not a member", c.axis),
                    ));
                }
                self.group_admit(g, GroupFbClass::Membership, fb)?;
                let grp = &mut self.groups.list[g];
                grp.members.retain(|m| m.1 != ax);
                grp.path.clear();
                self.groups.of_axis[ax] = None;
                Ok(self.group_admin_done(g))
            }
            GroupCommand::UngroupAllAxes { .. } => {
                self.group_admit(g, GroupFbClass::Ungroup, "MC_UngroupAllAxes")?;
                self.group_abort_motion(g, true);
                let grp = &mut self.groups.list[g];
                for (_, ax) in grp.members.drain(..) {
                    self.groups.of_axis[ax] = None;
                }
                grp.path.clear();
                grp.error = ErrorId::NONE;
                Ok(self.group_admin_done(g))
            }
            GroupCommand::GroupReadConfiguration { ident_in_group, .. } => {
                let grp = &self.groups.list[g];
                let list: Vec<(String, u32)> = grp
                    .members
                    .iter()
                    .filter(|m| ident_in_group == 0 || m.0 == ident_in_group)
                    .map(|m| (str::to_owned(&self.axes[m.1].name), m.0))
                    .collect();
                if list.is_empty() && ident_in_group != 0 {
                    return Err(invalid(
                        &gname,
                        "MC_GroupReadConfiguration",
                        format!("IdentInGroup = {ident_in_group} is not a member"),
                    ));
                }
                Ok(self.group_untracked(GroupReply::Configuration(list)))
            }
            GroupCommand::GroupEnable { .. } => {
                self.group_admit(g, GroupFbClass::Enable, "MCV_GroupEnable")?;
                self.groups.list[g].disabled = false;
                Ok(self.group_admin_done(g))
            }
            GroupCommand::GroupDisable { .. } => {
                self.group_admit(g, GroupFbClass::Disable, "MC_GroupDisable")?;
                self.group_abort_motion(g, true);
                let grp = &mut self.groups.list[g];
                grp.disabled = true;
                grp.error = ErrorId::NONE;
                Ok(self.group_admin_done(g))
            }
            // MC_GrpReset resets the members in ErrorStop with MC_Reset, which the engine
            // owns: it goes through `admit_reset`, the members' MC_Reset and `finish_reset`.
            GroupCommand::GroupReset { .. } => Err(reject(
                ERR_SIM_NOT_IMPLEMENTED,
                format!("group '{gname}': MC_GrpReset is composed by the engine (GroupCx::admit_reset, the members' MC_Reset, GroupCx::finish_reset)"),
            )),
            GroupCommand::GroupReadStatus { .. } => {
                let s = self.groups.status(g, self.axes);
                Ok(self.group_untracked(GroupReply::Status(Box::new(s))))
            }
            GroupCommand::GroupReadError { .. } => {
                let e = self.groups.list[g].error;
                Ok(self.group_untracked(GroupReply::Error(e)))
            }
            GroupCommand::GroupReadActualPosition { .. } => {
                let v = self.groups.list[g]
                    .axes()
                    .map(|i| self.axes[i].act_pos)
                    .collect();
                Ok(self.group_untracked(GroupReply::Values(v)))
            }
            GroupCommand::GroupReadActualVelocity { .. } => {
                if self.profile.isg() {
                    return Err(reject(
                        ERR_SIM_NOT_IMPLEMENTED,
                        format!("group '{gname}': MC_GroupReadActualVelocity is not implemented by the ISG platform (§3.2)"),
                    ));
                }
                let v = self.groups.list[g]
                    .axes()
                    .map(|i| self.axes[i].act_velo)
                    .collect();
                Ok(self.group_untracked(GroupReply::Values(v)))
            }
            GroupCommand::GroupSetOverride(c) => {
                let fb = "MC_GroupSetOverride";
                for (f, v) in [
                    ("VelFactor", c.vel_factor),
                    ("AccFactor", c.acc_factor),
                    ("JerkFactor", c.jerk_factor),
                ] {
                    finite(&gname, fb, f, v)?;
                    if c.enable && !(0.0..=1.0).contains(&v) {
                        return Err(invalid(&gname, fb, format!("{f} = {v} must be in [0, 1]")));
                    }
                }
                if c.enable {
                    let grp = &mut self.groups.list[g];
                    grp.override_enabled = true;
                    if grp.override_factor != c.vel_factor {
                        grp.override_factor = c.vel_factor;
                        self.group_replan_override(g);
                    }
                } else {
                    self.groups.list[g].override_enabled = false;
                }
                let en = self.groups.list[g].override_enabled;
                Ok(self.group_untracked(GroupReply::Enabled(en)))
            }
            GroupCommand::MoveLinearAbsolute(c) => self.move_linear(g, c, false),
            GroupCommand::MoveLinearRelative(c) => self.move_linear(g, c, true),
            GroupCommand::GroupHalt(c) => {
                let fb = "MC_GroupHalt";
                let d = Dyn {
                    velocity: 0.0,
                    acceleration: 0.0,
                    deceleration: c.deceleration,
                    jerk: c.jerk,
                };
                dynamics(&gname, fb, None, &d)?;
                only_aborting(&gname, fb, c.buffer_mode)?;
                self.group_admit(g, GroupFbClass::Halt, fb)?;
                let id = self.group_instance(g, GroupFbKind::GroupHalt, CommandState::Active);
                self.group_start_stop(g, id, PathKind::Halt, d);
                Ok(Self::group_tracked(id))
            }
            GroupCommand::GroupStop(c) => {
                let fb = "MC_GroupStop";
                let d = Dyn {
                    velocity: 0.0,
                    acceleration: 0.0,
                    deceleration: c.deceleration,
                    jerk: c.jerk,
                };
                dynamics(&gname, fb, None, &d)?;
                self.group_admit(g, GroupFbClass::Stop, fb)?;
                let id = self.group_instance(g, GroupFbKind::GroupStop, CommandState::Active);
                // A previous MC_GroupStop is taken over.
                if let Some(l) = self.groups.list[g].lock.take() {
                    let st = if l.done {
                        None
                    } else {
                        Some(CommandState::Aborted)
                    };
                    if let Some(s) = st {
                        self.groups.set(self.fbs, l.owner, s);
                    }
                }
                self.groups.list[g].lock = Some(GroupLock {
                    owner: id,
                    execute: true,
                    done: false,
                });
                self.group_start_stop(g, id, PathKind::Stop, d);
                Ok(Self::group_tracked(id))
            }
            GroupCommand::PathSelect(c) => {
                let fb = "MC_PathSelect";
                let n = self.groups.list[g].members.len();
                if c.points.is_empty() {
                    return Err(invalid(&gname, fb, "the path has no points".into()));
                }
                for (k, p) in c.points.iter().enumerate() {
                    if p.len() != n {
                        return Err(invalid(
                            &gname,
                            fb,
                            format!("point {k} has {} values, the group has {n} axes", p.len()),
                        ));
                    }
                    for (m, v) in p.iter().enumerate() {
                        finite(&gname, fb, &format!("Points[{k}][{m}]"), *v)?;
                    }
                    self.check_soft_limits(g, fb, p)?;
                }
                self.group_admit(g, GroupFbClass::ReadWrite, fb)?;
                self.groups.list[g].path = c.points;
                Ok(self.group_admin_done(g))
            }
            GroupCommand::MovePath(c) => {
                let fb = "MC_MovePath";
                let d = Dyn {
                    velocity: c.velocity,
                    acceleration: c.acceleration,
                    deceleration: c.deceleration,
                    jerk: c.jerk,
                };
                dynamics(&gname, fb, Some(c.velocity), &d)?;
                only_aborting(&gname, fb, c.buffer_mode)?;
                if self.groups.list[g].path.is_empty() {
                    return Err(invalid(
                        &gname,
                        fb,
                        "no path selected (MC_PathSelect)".into(),
                    ));
                }
                self.group_admit(g, GroupFbClass::Move, fb)?;
                self.members_ready(g, fb)?;
                let first = self.groups.list[g].path[0].clone();
                self.group_safety_check(g, fb, true, &first, c.velocity)?;
                let queue: VecDeque<Vec<f64>> = self.groups.list[g].path.iter().cloned().collect();
                let id = self.group_instance(g, GroupFbKind::MovePath, CommandState::Active);
                self.group_start_move(g, id, queue, d);
                Ok(Self::group_tracked(id))
            }
            GroupCommand::NotImplemented { fb, .. } => Err(reject(
                ERR_SIM_NOT_IMPLEMENTED,
                format!("group '{gname}': {fb} is not implemented (marked * in §3.2)"),
            )),
        }
    }

    /// MC_GrpReset, first half: the group admits it; returns the members in ErrorStop, which
    /// the caller resets with MC_Reset (in isg_mcp their MC message buffers are cleared too,
    /// R-ERR-3) before [`Self::finish_reset`].
    pub fn admit_reset(&mut self, g: usize) -> Result<Vec<usize>, Rejection> {
        self.group_admit(g, GroupFbClass::Reset, "MC_GrpReset")?;
        Ok(self
            .members(g)
            .into_iter()
            .filter(|&ax| !self.axes[ax].error_id.is_none())
            .collect())
    }

    /// MC_GrpReset, second half: the group error is cleared; the instance is Done in the next
    /// cycle.
    pub fn finish_reset(&mut self, g: usize) -> GroupCallReply {
        let id = self.group_instance(g, GroupFbKind::GroupReset, CommandState::Busy);
        self.groups.list[g].error = ErrorId::NONE;
        self.groups.instant_done.push(id);
        Self::group_tracked(id)
    }

    fn check_soft_limits(&self, g: usize, fb: &str, p: &[f64]) -> Result<(), Rejection> {
        for (k, ax) in self.groups.list[g].axes().enumerate() {
            let a = &self.axes[ax];
            let c = &a.cfg;
            if (c.en_max_soft_pos_limit && p[k] > c.max_soft_pos_limit)
                || (c.en_min_soft_pos_limit && p[k] < c.min_soft_pos_limit)
            {
                return Err(reject(
                    SOFT_LIMIT_TARGET,
                    format!(
                        "group '{}': {fb}: target {} of axis '{}' is outside the software limits",
                        self.groups.list[g].name, p[k], a.name
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Members must be at rest or driven by this group (no single-axis motion to take over).
    fn members_ready(&self, g: usize, fb: &str) -> Result<(), Rejection> {
        for ax in self.groups.list[g].axes() {
            let a = &self.axes[ax];
            let busy = !a.group_motion
                && (a.job.is_some()
                    || a.lock.is_some()
                    || a.homing.is_some()
                    || a.coupling.is_some()
                    || a.torque.is_some());
            if busy {
                return Err(reject(
                    ERR_SIM_TRANSITION_NOT_ALLOWED,
                    format!(
                        "group '{}': {fb}: member axis '{}' is busy ({:?})",
                        self.groups.list[g].name,
                        a.name,
                        a.state()
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The group of a command instance's Execute falling edge (MC_GroupStop unlock).
    pub fn group_set_execute(&mut self, id: CmdId, execute: bool) -> Option<GroupCallReply> {
        let i = self.groups.instances.get_mut(&id)?;
        if i.execute && !execute && i.state.is_final() {
            i.cleared = true;
        }
        i.execute = execute;
        let (g, kind) = (i.group, i.kind);
        if kind == GroupFbKind::GroupStop && !execute {
            let grp = &mut self.groups.list[g];
            if let Some(l) = grp.lock.as_mut().filter(|l| l.owner == id) {
                l.execute = false;
                if l.done {
                    grp.lock = None;
                }
            }
        }
        Some(Self::group_tracked(id))
    }

    /// Cancel of a group motion goal = MC_GroupHalt with the command's own deceleration.
    pub fn group_cancel(&mut self, id: CmdId) -> Option<Result<(), Rejection>> {
        let i = *self.groups.instances.get(&id)?;
        if i.state.is_final() {
            return Some(Ok(()));
        }
        let g = i.group;
        let running = self.groups.list[g]
            .job
            .as_ref()
            .filter(|j| j.owner == Some(id) && j.kind == PathKind::Move)
            .map(|j| j.dynamics);
        if let Some(d) = running {
            let hid = self.group_instance(g, GroupFbKind::GroupHalt, CommandState::Active);
            self.group_start_stop(g, hid, PathKind::Halt, d);
        }
        Some(Ok(()))
    }
}

/// Unit direction and length from `a` to `b` (zero direction for zero length).
fn unit(a: &[f64], b: &[f64]) -> (Vec<f64>, f64) {
    let d: Vec<f64> = b.iter().zip(a).map(|(x, y)| x - y).collect();
    let len = d.iter().map(|x| x * x).sum::<f64>().sqrt();
    if len <= 1e-12 {
        return (vec![0.0; d.len()], 0.0);
    }
    (d.iter().map(|x| x / len).collect(), len)
}

impl Groups {
    /// The index of the named group.
    pub fn index_of(&self, name: &str) -> Result<usize, Rejection> {
        self.index
            .get(name)
            .copied()
            .ok_or_else(|| Rejection::unknown_object("group", name))
    }

    /// The status of one group (MC_GroupReadStatus and the snapshot).
    pub fn status(&self, g: usize, axes: &[Axis]) -> GroupStatus {
        let grp = &self.list[g];
        let state = grp.state(axes);
        let v = grp.path_vel;
        let a = grp.path_acc;
        let moving = v.abs() > V_REST;
        GroupStatus {
            name: grp.name.clone(),
            state,
            group_moving: state == GroupState::Moving,
            group_homing: state == GroupState::Homing,
            group_error_stop: state == GroupState::ErrorStop,
            group_standby: state == GroupState::Standby,
            group_stopping: state == GroupState::Stopping,
            group_disabled: state == GroupState::Disabled,
            constant_velocity: moving && a.abs() <= 1e-9,
            accelerating: moving && a * v > 1e-9,
            decelerating: moving && a * v < -1e-9,
            in_position: grp.job.is_none()
                && grp.axes().all(|i| {
                    let x = &axes[i];
                    (x.act_pos - x.set.pos).abs() <= x.cfg.position_range_window
                }),
            axes: grp.axes().map(|i| str::to_owned(&axes[i].name)).collect(),
            idents: grp.members.iter().map(|m| m.0).collect(),
            error_id: grp.error,
            override_factor: grp.override_factor,
            path_velocity: v,
            path_acceleration: a,
            set_position: grp.axes().map(|i| axes[i].set.pos).collect(),
            act_position: grp.axes().map(|i| axes[i].act_pos).collect(),
            path_points: grp.path.len(),
        }
    }

    /// The status of a group by name.
    pub fn by_name(&self, name: &str, axes: &[Axis]) -> Option<GroupStatus> {
        self.index.get(name).map(|&g| self.status(g, axes))
    }

    /// Group names in configuration order.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.list.iter().map(|g| g.name.as_str())
    }

    /// Hook for single-axis commands: a member of a moving/stopping group refuses motion
    /// (`isg`: the ISG profile's error id).
    pub fn blocks_axis(
        &self,
        ax: usize,
        fb: &str,
        axes: &[Axis],
        isg: bool,
    ) -> Result<(), Rejection> {
        let Some(g) = self.of_axis.get(ax).copied().flatten() else {
            return Ok(());
        };
        let grp = &self.list[g];
        if grp.job.is_some() || grp.lock.is_some() {
            let id = if isg {
                ERR_SIM_TRANSITION_NOT_ALLOWED
            } else {
                single_axis::error_ids::AXIS_CANNOT_BE_STARTED
            };
            return Err(reject(
                id,
                format!(
                    "axis '{}': {fb} not allowed while its group '{}' is {:?}",
                    axes[ax].name,
                    grp.name,
                    grp.state(axes)
                ),
            ));
        }
        Ok(())
    }

    /// Builds the groups of the configuration (R-ARCH-4).
    pub fn build(
        &mut self,
        cfg: &[GroupConfig],
        index: &HashMap<String, usize>,
        n_axes: usize,
    ) -> Result<(), Rejection> {
        self.of_axis = vec![None; n_axes];
        for (k, gc) in cfg.iter().enumerate() {
            if gc.name.is_empty() {
                return Err(reject(
                    ErrorId::VALUE_OUT_OF_RANGE,
                    format!("group #{k}: empty group name"),
                ));
            }
            if self.index.insert(gc.name.clone(), k).is_some() {
                return Err(reject(
                    ErrorId::VALUE_OUT_OF_RANGE,
                    format!("group '{}' is configured twice", gc.name),
                ));
            }
            let mut grp = Group::new(gc.name.clone());
            for (m, name) in gc.axes.iter().enumerate() {
                let ax = index
                    .get(name)
                    .copied()
                    .ok_or_else(|| Rejection::unknown_object("axis", name))?;
                if let Some(o) = self.of_axis[ax] {
                    return Err(reject(
                        ERR_SIM_INVALID_PARAMETER,
                        format!(
                            "group '{}': axis '{name}' is already in group '{}'",
                            gc.name, cfg[o].name
                        ),
                    ));
                }
                self.of_axis[ax] = Some(k);
                grp.members.push((m as u32 + 1, ax));
            }
            self.list.push(grp);
        }
        Ok(())
    }
}

// The group's path motion: its own module (this module's private helpers are its too).
mod motion;
