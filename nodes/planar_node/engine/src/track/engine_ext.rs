//! The engine's track hooks: track methods (§3.3), JoinTrack / LeaveTrack / MoveOnTrack /
//! AdoptTrackOrientation (§3.2), operation modes (§2.5), and the on-track cycle with gap
//! control (§5.6.3) and network transitions (§5.6.5).

use super::gap::{reach, step_ok, AIM_INSIDE, GAP_EPS};
use super::geometry::{GeometryError, TrackPose};
use super::{GearIn, Master, SyncDirections, Track, TrackMotion, TrackOperationMode, TrackTarget};
use crate::admission::CommandKind;
use crate::command::PlanarCommand;
use crate::engine::{end, ev, traj_err, PlanarEngine};
use crate::errors::*;
use crate::geometry::V2;
use crate::guard::Grid;
use crate::motion::{in_c_window, modulo_target, Kin2};
use crate::snapshot::{OnTrackSnapshot, PlanarReply, ReplyValue, TrackSnapshot};
use crate::types::*;
use motion_core::trajectory::{Limits, Profile1, State1};
use motion_core::{CmdId, CommandState, ErrorId, Rejection};

/// A gap-limited follower re-plans at most every this many cycles while its leader moves.
const REPLAN_CYCLES: u32 = 8;
/// ... and only when its limit moved by more than this \[mm\].
const REPLAN_MIN: f64 = 0.5;
/// A waiting (standing) follower resumes once its limit is this far ahead \[mm\].
const RESUME_MIN: f64 = 1e-3;
/// Positions closer than this are "at the target" \[mm\].
const AT_TARGET: f64 = 1e-9;

fn geo_err(who: &str, e: GeometryError) -> Rejection {
    reject(E_GEOMETRY_INVALID, format!("{who}: {}", e.0))
}

fn reply(id: CmdId, value: ReplyValue) -> Result<PlanarReply, Rejection> {
    Ok(PlanarReply {
        id,
        warning_id: ErrorId::NONE,
        value,
    })
}

/// Heading equivalent to `h` \[deg\] nearest to `c` \[deg\].
fn nearest_equivalent(h: f64, c: f64) -> f64 {
    h + 360.0 * ((c - h) / 360.0).round()
}

/// The command target `x` clamped by the gap limits in the direction of travel; a target
/// exactly on the limit stays reachable, a clamped one lies just inside.
fn clamp_target(x: f64, r: f64, fwd: f64, bwd: f64) -> f64 {
    if x >= r {
        if x <= fwd + GAP_EPS {
            x
        } else {
            fwd - AIM_INSIDE
        }
    } else if x >= bwd - GAP_EPS {
        x
    } else {
        bwd + AIM_INSIDE
    }
}

fn limits_of(d: &Dynamics) -> Limits {
    d.limits()
}

impl PlanarEngine {
    /// GetPositionAt without a command: the pose at `arc_length` in the track's current part
    /// position. Pure, so the shell can sample whole tracks through the runtime's read-only
    /// query path (drawing markers must not flood `~/command_status`).
    pub fn track_position_at(
        &self,
        track: &str,
        arc_length: f64,
    ) -> Result<PositionXYC, Rejection> {
        let k = self.track(track)?;
        let who = self.track_who(k);
        finite(&who, "arc_length", arc_length)?;
        let t = &self.tracks[k];
        if t.geo.length() <= 0.0 {
            return Err(reject(E_INVALID_STATE, format!("{who}: no geometry")));
        }
        if !t.geo.closed() && !(0.0..=t.geo.length()).contains(&arc_length) {
            return Err(reject(
                E_INVALID_PARAMETER,
                format!(
                    "{who}: arc_length = {arc_length} outside [0, {}]",
                    t.geo.length()
                ),
            ));
        }
        let mut p = t.geo.pose_at(arc_length);
        p.p += self.track_shift_at(k, 0);
        let refid = if self.coordinate_systems.len() == 1 && t.cs == 0 {
            0
        } else {
            t.cs
        };
        Ok(PositionXYC::with_ref(p.p.x, p.p.y, p.heading_deg(), refid))
    }

    pub(crate) fn track(&self, name: &str) -> Result<usize, Rejection> {
        self.track_idx
            .get(name)
            .copied()
            .ok_or_else(|| Rejection::unknown_object("track", name))
    }

    // ------------------------------------------------------------------ operation modes (§2.5)

    /// Operation modes of all tracks, derived from the movers (O(movers + tracks)).
    pub(crate) fn track_modes(&self) -> Vec<TrackOperationMode> {
        let mut moving = vec![false; self.tracks.len()];
        let mut config = vec![false; self.tracks.len()];
        for m in &self.movers {
            if let Some(t) = &m.track {
                if t.active() {
                    moving[t.track] = true;
                    for &k in &t.route {
                        moving[k] = true;
                    }
                }
            }
            if let Some((k, _, _)) = m.joining {
                config[k] = true;
            }
            if let Some(k) = m.leaving {
                config[k] = true;
            }
        }
        self.tracks
            .iter()
            .enumerate()
            .map(|(k, t)| {
                if t.sm.state != PlanarState::Enabled {
                    TrackOperationMode::Uninitialized
                } else if moving[k] {
                    TrackOperationMode::Moving
                } else if config[k] {
                    TrackOperationMode::Configuring
                } else {
                    TrackOperationMode::Standing
                }
            })
            .collect()
    }

    fn require_track_ready(&self, k: usize, who: &str) -> Result<TrackOperationMode, Rejection> {
        let t = &self.tracks[k];
        if t.sm.state != PlanarState::Enabled {
            return Err(reject(
                E_TRACK_NOT_READY,
                format!(
                    "{who}: track '{}' is {:?} (Uninitialized)",
                    t.name, t.sm.state
                ),
            ));
        }
        Ok(self.track_modes()[k])
    }

    // ------------------------------------------------------------------ track methods (§3.3)

    pub(crate) fn track_who(&self, k: usize) -> String {
        format!("track '{}'", self.tracks[k].name)
    }

    fn require_disabled_track(&self, k: usize) -> Result<(), Rejection> {
        let t = &self.tracks[k];
        if t.sm.state != PlanarState::Disabled {
            return Err(reject(
                E_INVALID_STATE,
                format!(
                    "track '{}': geometry changes need state Disabled, is {:?}",
                    t.name, t.sm.state
                ),
            ));
        }
        Ok(())
    }

    fn require_unlocked(&self, k: usize) -> Result<(), Rejection> {
        let t = &self.tracks[k];
        if t.geo.closed() {
            return Err(reject(
                E_TRACK_LOCKED,
                format!("track '{}': closed loop, nothing can be appended", t.name),
            ));
        }
        if let Some(&o) = t.locked_by.first() {
            return Err(reject(
                E_TRACK_LOCKED,
                format!(
                    "track '{}': locked by the link of track '{}' (Clear that track first)",
                    t.name, self.tracks[o].name
                ),
            ));
        }
        Ok(())
    }

    /// A point of a geometry call in the track's coordinate system.
    fn track_point(&self, k: usize, field: &str, p: &PositionXYC) -> Result<V2, Rejection> {
        let who = self.track_who(k);
        p.check_finite(&who, field)?;
        let (cs, v) = self.resolve(&who, p.x, p.y, p.reference_id)?;
        if cs != self.tracks[k].cs {
            return Err(reject(
                E_GEOMETRY_INVALID,
                format!(
                    "{who}: {field} is in coordinate system 0x{cs:08X}, the track in 0x{:08X}",
                    self.tracks[k].cs
                ),
            ));
        }
        // Stored in the coordinates of the part position the geometry was defined in.
        Ok(v - self.track_shift_at(k, 0))
    }

    fn link(&mut self, from: usize, to: usize) {
        if !self.tracks[from].next.contains(&to) {
            self.tracks[from].next.push(to);
        }
        if !self.tracks[to].prev.contains(&from) {
            self.tracks[to].prev.push(from);
        }
    }

    fn check_position_index(&self, k: usize, index: u32, which: &str) -> Result<(), Rejection> {
        if index == 0 {
            return Ok(());
        }
        let t = &self.tracks[k];
        let ok = self
            .parts
            .iter()
            .find(|p| p.oid == t.part_oid)
            .or(self.parts.first().filter(|_| t.part_oid == 0))
            .is_some_and(|p| p.positions.contains_key(&index));
        if !ok {
            return Err(reject(
                E_INVALID_POSITION_INDEX,
                format!(
                    "track '{}': {which} part position index {index} does not exist",
                    t.name
                ),
            ));
        }
        Ok(())
    }

    fn start_from_track(
        &mut self,
        k: usize,
        o: usize,
        adv: super::TrackLinkAdvancedOptions,
    ) -> Result<PlanarReply, Rejection> {
        let who = self.track_who(k);
        self.require_disabled_track(k)?;
        if k == o {
            return Err(reject(
                E_GEOMETRY_INVALID,
                format!("{who}: StartFromTrack with itself"),
            ));
        }
        let delta = self.track_shift_at(o, adv.other_track_part_position_index)
            - self.track_shift_at(k, adv.this_track_part_position_index);
        let other = &self.tracks[o];
        let Some(mut end) = other.geo.end_pose().filter(|_| !other.geo.closed()) else {
            return Err(reject(
                E_GEOMETRY_INVALID,
                format!(
                    "{who}: track '{}' is empty or a closed loop (no free end)",
                    other.name
                ),
            ));
        };
        end.p += delta;
        let same_part = other.part_oid == self.tracks[k].part_oid;
        let t = &self.tracks[k];
        if !t.geo.is_empty() {
            // Further calls only add a logical link to a track on another part.
            let fits = t.geo.start_pose().is_some_and(|s| s.continuous_with(&end));
            if same_part || !t.start_linked || !fits {
                return Err(reject(
                    if t.start_linked {
                        E_ALREADY_CONNECTED
                    } else {
                        E_GEOMETRY_INVALID
                    },
                    format!("{who}: StartFromTrack needs an empty track (start already defined)"),
                ));
            }
        } else {
            self.tracks[k].geo.set_start(end);
            self.tracks[k].start_linked = true;
        }
        if !self.tracks[o].locked_by.contains(&k) {
            self.tracks[o].locked_by.push(k);
        }
        self.link(o, k);
        if adv.link_only_in_specified_part_positions {
            let (fi, ti) = (
                self.track_part_index(o, adv.other_track_part_position_index),
                self.track_part_index(k, adv.this_track_part_position_index),
            );
            self.tracks[o].link_only.push((k, fi, ti));
        }
        self.done_now()
    }

    fn end_at_track(
        &mut self,
        k: usize,
        o: usize,
        adv: super::TrackLinkAdvancedOptions,
    ) -> Result<PlanarReply, Rejection> {
        let who = self.track_who(k);
        self.require_disabled_track(k)?;
        let delta = self.track_shift_at(o, adv.other_track_part_position_index)
            - self.track_shift_at(k, adv.this_track_part_position_index);
        let other = &self.tracks[o];
        let Some(mut start) = other.geo.start_pose().filter(|_| !other.geo.closed()) else {
            return Err(reject(
                E_GEOMETRY_INVALID,
                format!(
                    "{who}: track '{}' is empty or a closed loop (no free start)",
                    other.name
                ),
            ));
        };
        start.p += delta;
        let same_part = other.part_oid == self.tracks[k].part_oid;
        let t = &self.tracks[k];
        if t.geo.is_empty() || t.geo.closed() {
            return Err(reject(
                E_GEOMETRY_INVALID,
                format!("{who}: EndAtTrack needs a non-empty open track"),
            ));
        }
        if t.end_linked {
            let fits = t.geo.end_pose().is_some_and(|e| e.continuous_with(&start));
            if same_part || !fits {
                return Err(reject(
                    E_ALREADY_CONNECTED,
                    format!("{who}: the end is already linked"),
                ));
            }
        } else {
            self.require_unlocked(k)?;
            self.tracks[k]
                .geo
                .transition_to(&start)
                .map_err(|e| geo_err(&who, e))?;
            self.tracks[k].end_linked = true;
            self.tracks[k].locked_by.push(k);
        }
        self.link(k, o);
        if adv.link_only_in_specified_part_positions {
            let (fi, ti) = (
                self.track_part_index(k, adv.this_track_part_position_index),
                self.track_part_index(o, adv.other_track_part_position_index),
            );
            self.tracks[k].link_only.push((o, fi, ti));
        }
        self.done_now()
    }

    fn track_clear(&mut self, k: usize) -> Result<PlanarReply, Rejection> {
        self.require_disabled_track(k)?;
        if !self.tracks[k].order.is_empty() {
            return Err(reject(
                E_INVALID_STATE,
                format!("{}: movers on the track", self.track_who(k)),
            ));
        }
        for t in &mut self.tracks {
            t.prev.retain(|&x| x != k);
            t.next.retain(|&x| x != k);
            t.locked_by.retain(|&x| x != k);
        }
        let t = &mut self.tracks[k];
        t.geo = Default::default();
        t.prev.clear();
        t.next.clear();
        t.locked_by.clear();
        t.start_linked = false;
        t.end_linked = false;
        self.done_now()
    }

    fn track_enable(&mut self, k: usize) -> Result<PlanarReply, Rejection> {
        let who = self.track_who(k);
        let t = &self.tracks[k];
        if t.sm.state == PlanarState::Disabled {
            if t.geo.length() <= 0.0 {
                return Err(reject(
                    E_GEOMETRY_INVALID,
                    format!("{who}: Enable without geometry"),
                ));
            }
            if self.parts.len() > 1 && t.part_oid == 0 {
                return Err(reject(
                    E_GEOMETRY_INVALID,
                    format!("{who}: PartOID missing with more than one part"),
                ));
            }
            self.track_lies_on_part(k)?;
        }
        let id = self.new_id();
        let timing = self.timing;
        let r = self.tracks[k]
            .sm
            .enable(id, &timing, &who, &mut self.pending)?;
        ev(
            &mut self.pending,
            id,
            if r == crate::state::Accepted::AlreadyThere {
                CommandState::Done
            } else {
                CommandState::Active
            },
        );
        reply(id, ReplyValue::None)
    }

    /// The track's geometry lies completely on its part (§1.6, §5.4); no part: always.
    pub(crate) fn track_lies_on_part(&self, k: usize) -> Result<(), Rejection> {
        let who = self.track_who(k);
        let t = &self.tracks[k];
        let part = if t.part_oid != 0 {
            self.parts.iter().find(|p| p.oid == t.part_oid)
        } else {
            self.parts.first()
        };
        if let Some(p) = part {
            let (pcs, o) = p.origin();
            let side = crate::geometry::STATOR_SIDE;
            let on = |q: V2| {
                let l = q - o;
                p.tiles.iter().any(|tl| {
                    l.x >= tl.x - 1e-6
                        && l.x <= tl.x + side + 1e-6
                        && l.y >= tl.y - 1e-6
                        && l.y <= tl.y + side + 1e-6
                })
            };
            let shift = self.track_shift_at(k, 0);
            if pcs != t.cs || !t.geo.samples(5.0).into_iter().all(|q| on(q + shift)) {
                return Err(reject(
                    E_GEOMETRY_INVALID,
                    format!(
                        "{who}: the track does not lie completely on part '{}'",
                        p.name
                    ),
                ));
            }
        }
        Ok(())
    }

    fn track_disable(&mut self, k: usize) -> Result<PlanarReply, Rejection> {
        if !self.tracks[k].order.is_empty()
            || self
                .movers
                .iter()
                .any(|m| m.joining.is_some_and(|j| j.0 == k) || m.leaving == Some(k))
        {
            return Err(reject(
                E_INVALID_STATE,
                format!("{}: Disable with movers on the track", self.track_who(k)),
            ));
        }
        let id = self.new_id();
        let timing = self.timing;
        let r = self.tracks[k].sm.disable(id, &timing, &mut self.pending);
        ev(
            &mut self.pending,
            id,
            if r == crate::state::Accepted::AlreadyThere {
                CommandState::Done
            } else {
                CommandState::Active
            },
        );
        reply(id, ReplyValue::None)
    }

    /// Track state machines (Enabling → Enabled etc., §2.1).
    pub(crate) fn step_tracks(&mut self, dt: f64) {
        for t in &mut self.tracks {
            if t.sm.advance(dt, true).is_some() {
                t.sm.complete(&mut self.pending);
            }
        }
    }

    /// Dispatch of the track commands and the on-track mover methods.
    pub(crate) fn track_command(&mut self, cmd: PlanarCommand) -> Result<PlanarReply, Rejection> {
        use PlanarCommand as C;
        let geometry = matches!(
            cmd,
            C::TrackAppendPosition { .. }
                | C::TrackAppendLine { .. }
                | C::TrackAppendCircle { .. }
                | C::TrackCloseLoop { .. }
                | C::TrackStartFromTrack { .. }
                | C::TrackEndAtTrack { .. }
                | C::TrackStartFromTrackAdvanced { .. }
                | C::TrackEndAtTrackAdvanced { .. }
                | C::TrackClear { .. }
                | C::TrackSetInitParameters { .. }
        );
        // The geometry is stored in CS coordinates of the part position it was defined in.
        let target_track = match &cmd {
            C::TrackAppendPosition { track, .. }
            | C::TrackAppendLine { track, .. }
            | C::TrackAppendCircle { track, .. }
            | C::TrackStartFromTrack { track, .. }
            | C::TrackStartFromTrackAdvanced { track, .. } => self.track_idx.get(track).copied(),
            _ => None,
        };
        if let Some(k) = target_track {
            if self.tracks[k].geo.is_empty() {
                self.tracks[k].geo_origin = self.track_shift_at(k, 0) + self.tracks[k].geo_origin;
            }
        }
        let r = self.track_command_inner(cmd);
        if geometry && r.is_ok() {
            self.rebuild_switches();
        }
        r
    }

    fn track_command_inner(&mut self, cmd: PlanarCommand) -> Result<PlanarReply, Rejection> {
        use PlanarCommand as C;
        match cmd {
            C::JoinTrack {
                mover,
                track,
                constraint,
                options,
            } => {
                let i = self.mover(&mover)?;
                let k = self.track(&track)?;
                self.join_track(i, k, constraint, options)
            }
            C::LeaveTrack {
                mover,
                target_position,
                constraint,
                options,
            } => {
                let i = self.mover(&mover)?;
                self.leave_track(i, target_position, constraint, options)
            }
            C::MoveOnTrack {
                mover,
                track,
                target_position,
                constraint,
                options,
            } => {
                let i = self.mover(&mover)?;
                let k = if track.is_empty() {
                    None
                } else {
                    Some(self.track(&track)?)
                };
                self.move_on_track(i, k, target_position, constraint, options)
            }
            C::AdoptTrackOrientation {
                mover,
                constraint,
                options,
            } => {
                let i = self.mover(&mover)?;
                self.adopt_track_orientation(i, constraint, options)
            }
            C::GearInPosOnTrackWithMasterMover {
                mover,
                master_mover,
                track_trail,
                master_sync_position,
                master_sync_position_track,
                slave_sync_position,
                slave_sync_position_track,
                constraint,
                options,
            } => {
                let i = self.mover(&mover)?;
                let j = self.mover(&master_mover)?;
                let trail = track_trail
                    .iter()
                    .map(|t| self.track(t))
                    .collect::<Result<Vec<_>, _>>()?;
                let mk = self.track(&master_sync_position_track)?;
                let sk = self.track(&slave_sync_position_track)?;
                self.gear_in(
                    i,
                    Master::Mover(j),
                    trail,
                    (master_sync_position, Some(mk)),
                    (slave_sync_position, sk),
                    constraint,
                    options,
                )
            }
            C::GearInPosOnTrack {
                mover,
                master_axis,
                track_trail,
                master_sync_position,
                slave_sync_position,
                slave_sync_position_track,
                constraint,
                options,
            } => {
                let i = self.mover(&mover)?;
                let Some(&a) = self.axis_idx.get(&master_axis) else {
                    return Err(reject(
                        E_INVALID_PARAMETER,
                        format!("mover '{mover}': unknown master axis '{master_axis}'"),
                    ));
                };
                let trail = track_trail
                    .iter()
                    .map(|t| self.track(t))
                    .collect::<Result<Vec<_>, _>>()?;
                let sk = self.track(&slave_sync_position_track)?;
                let o = super::GearInPosOnTrackWithMasterMoverOptions {
                    gap: options.gap,
                    in_sync_tolerance_distance: options.in_sync_tolerance_distance,
                    direction_slave_sync_position: options.direction_slave_sync_position,
                    modulo_tolerance_slave_sync_position: options
                        .modulo_tolerance_slave_sync_position,
                    allowed_slave_sync_directions: options.allowed_slave_sync_directions,
                    ..Default::default()
                };
                self.gear_in(
                    i,
                    Master::Axis(a),
                    trail,
                    (master_sync_position, None),
                    (slave_sync_position, sk),
                    constraint,
                    o,
                )
            }
            C::AxisPower { axis, enable } => {
                let a = self.axis(&axis)?;
                if !enable && self.axes[a].ax.moving() {
                    // Power off stops at once (set point frozen).
                    self.axes[a].ax.freeze();
                    let ev_ = &mut self.pending;
                    end(ev_, &mut self.axes[a].cmd, CommandState::Aborted);
                }
                self.axes[a].powered = enable;
                self.done_now()
            }
            C::AxisMoveAbsolute {
                axis,
                position,
                velocity,
                acceleration,
                deceleration,
                jerk,
            } => {
                let a = self.axis(&axis)?;
                let who = format!("axis '{axis}'");
                finite(&who, "position", position)?;
                let d = Dynamics {
                    velocity: finite(&who, "velocity", velocity)?,
                    acceleration: finite(&who, "acceleration", acceleration)?,
                    deceleration: finite(&who, "deceleration", deceleration)?,
                    jerk: finite(&who, "jerk", jerk)?,
                };
                self.axis_move(a, &who, |ax| ax.plan_to(position, &d))
            }
            C::AxisHalt {
                axis,
                deceleration,
                jerk,
            } => {
                let a = self.axis(&axis)?;
                let who = format!("axis '{axis}'");
                let d = Dynamics {
                    velocity: f64::MAX / 4.0,
                    acceleration: finite(&who, "deceleration", deceleration)?,
                    deceleration: finite(&who, "deceleration", deceleration)?,
                    jerk: finite(&who, "jerk", jerk)?,
                };
                self.axis_move(a, &who, |ax| ax.plan_stop(&d))
            }
            C::TrackAppendPosition { track, position } => {
                let k = self.track(&track)?;
                let p = self.track_point(k, "position", &position)?;
                self.require_disabled_track(k)?;
                self.require_unlocked(k)?;
                let who = self.track_who(k);
                self.tracks[k]
                    .geo
                    .append_position(p, position.c.to_radians())
                    .map_err(|e| geo_err(&who, e))?;
                self.done_now()
            }
            C::TrackAppendLine { track, start, end } => {
                let k = self.track(&track)?;
                let a = self.track_point(k, "start", &start)?;
                let b = self.track_point(k, "end", &end)?;
                self.require_disabled_track(k)?;
                self.require_unlocked(k)?;
                let who = self.track_who(k);
                let mut g = self.tracks[k].geo.clone();
                g.append_line(a, b).map_err(|e| geo_err(&who, e))?;
                self.tracks[k].geo = g;
                self.done_now()
            }
            C::TrackAppendCircle {
                track,
                start,
                end,
                center,
                clockwise,
            } => {
                let k = self.track(&track)?;
                let a = self.track_point(k, "start", &start)?;
                let b = self.track_point(k, "end", &end)?;
                let c = self.track_point(k, "center", &center)?;
                self.require_disabled_track(k)?;
                self.require_unlocked(k)?;
                let who = self.track_who(k);
                let mut g = self.tracks[k].geo.clone();
                g.append_circle(a, b, c, clockwise)
                    .map_err(|e| geo_err(&who, e))?;
                self.tracks[k].geo = g;
                self.done_now()
            }
            C::TrackCloseLoop { track } => {
                let k = self.track(&track)?;
                let who = self.track_who(k);
                self.require_disabled_track(k)?;
                let t = &self.tracks[k];
                if t.geo.is_empty() || t.geo.closed() {
                    return Err(reject(
                        E_GEOMETRY_INVALID,
                        format!("{who}: CloseLoop on an empty track or a closed loop"),
                    ));
                }
                if t.start_linked || t.end_linked || !t.locked_by.is_empty() {
                    return Err(reject(
                        E_TRACK_LOCKED,
                        format!("{who}: CloseLoop on a linked track"),
                    ));
                }
                let mut g = t.geo.clone();
                g.close_loop().map_err(|e| geo_err(&who, e))?;
                self.tracks[k].geo = g;
                self.done_now()
            }
            C::TrackStartFromTrack { track, other } => {
                let k = self.track(&track)?;
                let o = self.track(&other)?;
                self.start_from_track(k, o, Default::default())
            }
            C::TrackEndAtTrack { track, other } => {
                let k = self.track(&track)?;
                let o = self.track(&other)?;
                self.end_at_track(k, o, Default::default())
            }
            C::TrackStartFromTrackAdvanced {
                track,
                other,
                options,
            } => {
                let k = self.track(&track)?;
                let o = self.track(&other)?;
                self.check_position_index(k, options.this_track_part_position_index, "this")?;
                self.check_position_index(o, options.other_track_part_position_index, "other")?;
                self.start_from_track(k, o, options)
            }
            C::TrackEndAtTrackAdvanced {
                track,
                other,
                options,
            } => {
                let k = self.track(&track)?;
                let o = self.track(&other)?;
                self.check_position_index(k, options.this_track_part_position_index, "this")?;
                self.check_position_index(o, options.other_track_part_position_index, "other")?;
                self.end_at_track(k, o, options)
            }
            C::TrackClear { track } => {
                let k = self.track(&track)?;
                self.track_clear(k)
            }
            C::TrackEnable { track } => {
                let k = self.track(&track)?;
                self.track_enable(k)
            }
            C::TrackDisable { track } => {
                let k = self.track(&track)?;
                self.track_disable(k)
            }
            C::TrackReset { track } => {
                let k = self.track(&track)?;
                let who = self.track_who(k);
                let id = self.new_id();
                let timing = self.timing;
                let r = self.tracks[k].sm.reset(id, &timing, &who)?;
                ev(
                    &mut self.pending,
                    id,
                    if r == crate::state::Accepted::AlreadyThere {
                        CommandState::Done
                    } else {
                        CommandState::Active
                    },
                );
                reply(id, ReplyValue::None)
            }
            C::TrackAddToGroup { track, group } => {
                let k = self.track(&track)?;
                let g = self
                    .group_idx
                    .get(&group)
                    .copied()
                    .ok_or_else(|| Rejection::unknown_object("group", &group))?;
                let who = self.track_who(k);
                if self.groups[g].sm.state != PlanarState::Enabled {
                    return Err(reject(
                        E_GROUP_NOT_READY,
                        format!("{who}: group '{group}' is {:?}", self.groups[g].sm.state),
                    ));
                }
                if self.tracks[k].sm.state != PlanarState::Enabled {
                    return Err(reject(
                        E_INVALID_STATE,
                        format!("{who}: AddToGroup needs an Enabled track"),
                    ));
                }
                if let Some(og) = self.tracks[k].group {
                    return Err(reject(
                        E_GROUP_NOT_READY,
                        format!("{who}: already member of group '{}'", self.groups[og].name),
                    ));
                }
                let tube = self.tracks[k].build_tube();
                self.track_static_check(k, g, &tube)?;
                self.tracks[k].tube = tube;
                self.tracks[k].group = Some(g);
                self.done_now()
            }
            C::TrackRemoveFromGroup { track } => {
                let k = self.track(&track)?;
                self.tracks[k].group = None;
                self.tracks[k].tube.clear();
                self.done_now()
            }
            C::TrackGetLength { track } => {
                let k = self.track(&track)?;
                let id = self.new_id();
                ev(&mut self.pending, id, CommandState::Done);
                reply(id, ReplyValue::Scalar(self.tracks[k].length()))
            }
            C::TrackGetArcLengthClosestTo { track, point } => {
                let k = self.track(&track)?;
                let p = self.track_point(k, "point", &point)?;
                if self.tracks[k].geo.is_empty() {
                    return Err(reject(
                        E_INVALID_STATE,
                        format!("{}: no geometry", self.track_who(k)),
                    ));
                }
                let s = self.tracks[k].geo.closest(p);
                // (`p` is already in stored coordinates: track_point subtracted the shift.)
                let id = self.new_id();
                ev(&mut self.pending, id, CommandState::Done);
                reply(id, ReplyValue::Scalar(s))
            }
            C::TrackGetPositionAt { track, arc_length } => {
                let p = self.track_position_at(&track, arc_length)?;
                let id = self.new_id();
                ev(&mut self.pending, id, CommandState::Done);
                reply(id, ReplyValue::Position(p))
            }
            C::TrackSetInitParameters {
                track,
                max_mover_width,
                max_mover_height,
                check_static_collision,
                collision_range_mode,
                collision_range_start,
                collision_range_end,
            } => {
                let k = self.track(&track)?;
                let cfg = crate::config::TrackConfig {
                    max_mover_width,
                    max_mover_height,
                    check_static_collision,
                    collision_range_mode,
                    collision_range_start,
                    collision_range_end,
                    ..Default::default()
                };
                self.track_set_init_parameters(k, &cfg)
            }
            C::TrackGetPlanarObjectInfo { track } => {
                let k = self.track(&track)?;
                let id = self.new_id();
                ev(&mut self.pending, id, CommandState::Done);
                reply(
                    id,
                    ReplyValue::ObjectInfo(PlanarObjectInfo {
                        object_type: PlanarObjectType::Track,
                        id: self.tracks[k].oid,
                    }),
                )
            }
            other => Err(reject(
                ErrorId::NOT_IMPLEMENTED,
                format!("{other:?} is not implemented"),
            )),
        }
    }

    // ------------------------------------------------------------------ join / leave (§5.5)

    fn join_track(
        &mut self,
        i: usize,
        k: usize,
        constraint: DynamicConstraint,
        options: MoveToPositionOptions,
    ) -> Result<PlanarReply, Rejection> {
        let who = format!("mover '{}'", self.movers[i].name);
        self.require_enabled(i, "JoinTrack")?;
        self.require_mode(i, CommandKind::JoinTrack, "JoinTrack")?;
        let mode = self.require_track_ready(k, &who)?;
        if mode == TrackOperationMode::Moving {
            return Err(reject(
                E_TRACK_MODE_CONFLICT,
                format!(
                    "{who}: JoinTrack while track '{}' is Moving",
                    self.tracks[k].name
                ),
            ));
        }
        let m = &self.movers[i];
        let t = &self.tracks[k];
        if t.cs != m.cs {
            return Err(reject(
                E_TARGET_UNREACHABLE,
                format!("{who}: track '{}' is in another coordinate system", t.name),
            ));
        }
        let shift = self.track_shift_at(k, 0);
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
        for j in 0..self.movers.len() {
            let o = &self.movers[j];
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
        let refid = if self.coordinate_systems.len() == 1 && self.parts.is_empty() {
            0
        } else {
            t.cs
        };
        let r = self.move_to_position(
            i,
            PositionXYC::with_ref(pose.p.x, pose.p.y, c_end, refid),
            constraint,
            options,
        )?;
        let m = &mut self.movers[i];
        m.mode = CommandMode::JoiningTrack;
        m.joining = Some((k, s_j, options.use_orientation));
        Ok(r)
    }

    fn leave_track(
        &mut self,
        i: usize,
        target: PositionXYC,
        constraint: DynamicConstraint,
        options: MoveToPositionOptions,
    ) -> Result<PlanarReply, Rejection> {
        let who = format!("mover '{}'", self.movers[i].name);
        target.check_finite(&who, "target_position")?;
        self.require_enabled(i, "LeaveTrack")?;
        self.require_mode(i, CommandKind::LeaveTrack, "LeaveTrack")?;
        let Some(k) = self.movers[i].track.as_ref().map(|t| t.track) else {
            return Err(reject(
                E_INVALID_COMMAND_MODE,
                format!("{who}: not on a track"),
            ));
        };
        if self.track_modes()[k] == TrackOperationMode::Moving {
            return Err(reject(
                E_TRACK_MODE_CONFLICT,
                format!(
                    "{who}: LeaveTrack while track '{}' is Moving",
                    self.tracks[k].name
                ),
            ));
        }
        // The track is left at the start of the motion (§5.5): plan as a free move.
        let saved = self.movers[i].track.take();
        let mode = self.movers[i].mode;
        self.movers[i].mode = CommandMode::FreeMovement;
        match self.move_to_position(i, target, constraint, options) {
            Ok(r) => {
                self.movers[i].track = saved;
                self.detach_from_track(i);
                let m = &mut self.movers[i];
                m.mode = CommandMode::LeavingTrack;
                m.leaving = Some(k);
                m.c_mode = CCoordinateMode::Independent;
                Ok(r)
            }
            Err(e) => {
                let m = &mut self.movers[i];
                m.track = saved;
                m.mode = mode;
                Err(e)
            }
        }
    }

    /// Removes mover `i` from its track (Disable, LeaveTrack).
    pub(crate) fn detach_from_track(&mut self, i: usize) {
        let m = &mut self.movers[i];
        m.joining = None;
        if let Some(t) = m.track.take() {
            let order = &mut self.tracks[t.track].order;
            order.retain(|&x| x != i);
            self.renumber(t.track);
        }
    }

    fn renumber(&mut self, k: usize) {
        for (slot, &j) in self.tracks[k].order.iter().enumerate() {
            if let Some(t) = &mut self.movers[j].track {
                t.slot = slot;
            }
        }
    }

    /// Inserts mover `i` (already carrying its TrackMotion on `k`) into the track order.
    fn insert_into_order(&mut self, i: usize, k: usize) {
        let s_of =
            |e: &PlanarEngine, j: usize| e.movers[j].track.as_ref().map(|t| t.s()).unwrap_or(0.0);
        let t = &self.tracks[k];
        let s = s_of(self, i);
        let n = t.order.len();
        let pos = if t.geo.closed() && n > 0 {
            let l = t.length();
            let key = |x: f64| x.rem_euclid(l);
            // Cyclic order: after the mover with the largest key ≤ s (wrapping).
            let mut best: Option<(usize, f64)> = None;
            for (idx, &j) in t.order.iter().enumerate() {
                let d = (key(s) - key(s_of(self, j))).rem_euclid(l);
                if best.is_none_or(|(_, bd)| d < bd) {
                    best = Some((idx, d));
                }
            }
            best.map(|(idx, _)| idx + 1).unwrap_or(0)
        } else {
            t.order.partition_point(|&j| s_of(self, j) <= s)
        };
        self.tracks[k].order.insert(pos, i);
        self.renumber(k);
    }

    /// Bookkeeping of the track modes when axes come to rest (called by `finish_idle`).
    pub(crate) fn track_finish_idle(&mut self, i: usize) {
        let m = &self.movers[i];
        let xy_rest = m.path.is_none() && !m.xy.moving();
        if m.mode == CommandMode::JoiningTrack && xy_rest && m.xy_cmd.is_none() {
            let Some((k, s_j, dependent)) = m.joining else {
                self.movers[i].mode = CommandMode::FreeMovement;
                return;
            };
            let p = self.tracks[k].geo.pose_at(s_j).p + self.track_shift_at(k, 0);
            let m = &mut self.movers[i];
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
                self.insert_into_order(i, k);
            } else {
                // The approach was stopped (guard): no join.
                m.mode = CommandMode::FreeMovement;
            }
            return;
        }
        if m.mode == CommandMode::LeavingTrack && xy_rest && m.xy_cmd.is_none() {
            let m = &mut self.movers[i];
            m.leaving = None;
            m.mode = if in_c_window(m.c_out(), m.cfg.c_min, m.cfg.c_max) {
                CommandMode::FreeMovement
            } else {
                CommandMode::CRotationFreeMovement
            };
            return;
        }
        let Some(tm) = &self.movers[i].track else {
            return;
        };
        let k = tm.track;
        let s = tm.s();
        let adopt = tm.adopt;
        let m = &self.movers[i];
        let c_rest = !m.c.moving() && m.c_cmd.is_none();
        if adopt && c_rest {
            let h = self.tracks[k].geo.pose_at(s).heading_deg();
            let m = &mut self.movers[i];
            let c = m.c.pos;
            if (c - nearest_equivalent(h, c)).abs() <= 1e-6 {
                m.c_mode = CCoordinateMode::Dependent;
            }
            if let Some(t) = &mut m.track {
                t.adopt = false;
            }
        }
        let m = &mut self.movers[i];
        if c_rest
            && m.mode == CommandMode::CRotationOnTrack
            && in_c_window(m.c_out(), m.cfg.c_min, m.cfg.c_max)
        {
            m.mode = CommandMode::OnTrack;
        }
    }

    fn adopt_track_orientation(
        &mut self,
        i: usize,
        constraint: DynamicConstraint,
        options: super::AdoptTrackOrientationOptions,
    ) -> Result<PlanarReply, Rejection> {
        self.require_enabled(i, "AdoptTrackOrientation")?;
        self.require_mode(
            i,
            CommandKind::AdoptTrackOrientation,
            "AdoptTrackOrientation",
        )?;
        let tm = self.movers[i].track.as_ref().ok_or_else(|| {
            reject(
                E_INVALID_COMMAND_MODE,
                format!("mover '{}': not on a track", self.movers[i].name),
            )
        })?;
        let h = self.tracks[tm.track].geo.pose_at(tm.s()).heading_deg();
        let r = self.move_c(
            i,
            h,
            constraint,
            MoveCOptions {
                additional_turns: options.additional_turns,
                direction: options.direction,
            },
        )?;
        if let Some(t) = &mut self.movers[i].track {
            t.adopt = true;
        }
        Ok(r)
    }

    // ------------------------------------------------------------------ MoveOnTrack (§5.6)

    fn move_on_track(
        &mut self,
        i: usize,
        target_track: Option<usize>,
        target: f64,
        constraint: DynamicConstraint,
        options: super::MoveOnTrackOptions,
    ) -> Result<PlanarReply, Rejection> {
        let who = format!("mover '{}'", self.movers[i].name);
        finite(&who, "target_position", target)?;
        finite(&who, "options.gap", options.gap)?;
        finite(&who, "options.modulo_tolerance", options.modulo_tolerance)?;
        if options.gap < 0.0 || options.modulo_tolerance < 0.0 {
            return Err(reject(
                E_INVALID_PARAMETER,
                format!(
                    "{who}: gap = {} and modulo_tolerance = {} must not be negative",
                    options.gap, options.modulo_tolerance
                ),
            ));
        }
        self.require_enabled(i, "MoveOnTrack")?;
        self.require_mode(i, CommandKind::MoveOnTrack, "MoveOnTrack")?;
        self.require_group_ready(i)?;
        let dir = options.direction;
        let n = options.additional_turns;
        if n != 0 && matches!(dir, Direction::NonModulo | Direction::ShortestWay) {
            return Err(reject(
                E_INVALID_PARAMETER,
                format!("{who}: additional_turns = {n} not allowed with direction {dir:?}"),
            ));
        }
        if options.modulo_tolerance != 0.0 && dir == Direction::NonModulo {
            return Err(reject(
                E_INVALID_PARAMETER,
                format!("{who}: modulo_tolerance not allowed with NonModulo"),
            ));
        }
        let m = &self.movers[i];
        let Some(tm) = m.track.as_ref() else {
            return Err(reject(
                E_INVALID_COMMAND_MODE,
                format!("{who}: not on a track"),
            ));
        };
        let (dyn_, reduced) = Dynamics::resolve(
            &m.cfg.default_dynamics,
            &m.cfg.max_dynamics,
            &constraint,
            &who,
            "constraint",
        )?;
        let cur = tm.track;
        let kt = target_track.unwrap_or(cur);
        let modes = self.track_modes();
        let t = &self.tracks[kt];
        let l = t.length();
        let s = tm.s();
        let (r_target, route) = if kt == cur {
            if t.geo.closed() {
                let r = match dir {
                    Direction::NonModulo => target,
                    _ => modulo_target(target, tm.r, l, options.modulo_tolerance, dir, n).map_err(
                        |_| {
                            reject(
                                E_INVALID_PARAMETER,
                                format!("{who}: additional_turns not allowed with {dir:?}"),
                            )
                        },
                    )?,
                };
                (r, vec![])
            } else {
                if n != 0 {
                    return Err(reject(
                        E_INVALID_PARAMETER,
                        format!("{who}: additional_turns = {n} on an open track"),
                    ));
                }
                let unreachable = !(-1e-9..=l + 1e-9).contains(&target)
                    || dir == Direction::Positive && target < s - 1e-9
                    || dir == Direction::Negative && target > s + 1e-9;
                if unreachable {
                    return Err(reject(
                        E_TARGET_UNREACHABLE,
                        format!(
                            "{who}: target {target} not reachable on track '{}' (length {l}, at {s}, {dir:?})",
                            t.name
                        ),
                    ));
                }
                (tm.base + target.clamp(0.0, l), vec![])
            }
        } else {
            if dir == Direction::Negative {
                return Err(reject(
                    E_TARGET_UNREACHABLE,
                    format!("{who}: cross-track moves go forward only (direction Negative)"),
                ));
            }
            if n != 0 {
                return Err(reject(
                    E_INVALID_PARAMETER,
                    format!("{who}: additional_turns = {n} on a cross-track move"),
                ));
            }
            if !(-1e-9..=l + 1e-9).contains(&target) {
                return Err(reject(
                    E_TARGET_UNREACHABLE,
                    format!(
                        "{who}: target {target} outside track '{}' (length {l})",
                        t.name
                    ),
                ));
            }
            // The target track itself must be ready; the route uses Enabled tracks only.
            if t.sm.state != PlanarState::Enabled {
                return Err(reject(
                    E_TRACK_NOT_READY,
                    format!("{who}: target track '{}' is {:?}", t.name, t.sm.state),
                ));
            }
            let Some(route) = self.route(cur, kt) else {
                return Err(reject(
                    E_TARGET_UNREACHABLE,
                    format!(
                        "{who}: no route from track '{}' to track '{}'",
                        self.tracks[cur].name, t.name
                    ),
                ));
            };
            let mut r = tm.base + self.tracks[cur].length();
            for &k in &route[..route.len() - 1] {
                r += self.tracks[k].length();
            }
            (r + target.clamp(0.0, l), route)
        };
        for &k in std::iter::once(&cur).chain(route.iter()) {
            let t = &self.tracks[k];
            if t.sm.state != PlanarState::Enabled {
                return Err(reject(
                    E_TRACK_NOT_READY,
                    format!("{who}: track '{}' is {:?}", t.name, t.sm.state),
                ));
            }
            if modes[k] == TrackOperationMode::Configuring {
                return Err(reject(
                    E_TRACK_MODE_CONFLICT,
                    format!("{who}: MoveOnTrack while track '{}' is Configuring", t.name),
                ));
            }
        }
        let mut on_route = vec![cur];
        on_route.extend(route.iter().copied());
        self.check_track_tubes_free(i, &on_route)?;
        let tm = self.movers[i].track.as_ref().expect("on track");
        let prof = Profile1::to_position(tm.state(), r_target, 0.0, &limits_of(&dyn_))
            .map_err(|e| traj_err(&who, e))?;
        let id = self.new_id();
        let ev_ = &mut self.pending;
        let m = &mut self.movers[i];
        end(ev_, &mut m.xy_cmd, CommandState::Aborted);
        end(ev_, &mut m.halt_cmd, CommandState::Aborted);
        let tm = m.track.as_mut().expect("on track");
        tm.plan = Some((prof, 0.0));
        tm.plan_dyn = dyn_;
        tm.cmd_dyn = dyn_;
        tm.gear = None;
        tm.target = TrackTarget::Position(r_target);
        tm.gap = options.gap;
        tm.route = route;
        tm.braking = false;
        tm.limited = false;
        tm.since_replan = 0;
        m.xy_cmd = Some(id);
        m.guard_stop = false;
        m.warning = if reduced {
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

    /// Shortest route (by length of the tracks passed) from the end of `from` to `to` over
    /// traversable links between Enabled tracks: the tracks after `from`, ending with `to`
    /// (§5.6.5). The start track is never passed again (that would be a cycle).
    fn route(&self, from: usize, to: usize) -> Option<Vec<usize>> {
        let n = self.tracks.len();
        let mut dist = vec![f64::INFINITY; n];
        let mut prev = vec![usize::MAX; n];
        let mut done = vec![false; n];
        // A usable link from `u` to `k`: traversable now, to an Enabled track, never back to
        // the start track.
        let usable = |u: usize, k: usize| {
            k != from && self.tracks[k].sm.state == PlanarState::Enabled && self.traversable(u, k)
        };
        for &k in &self.tracks[from].next {
            if usable(from, k) {
                dist[k] = 0.0;
                prev[k] = from;
            }
        }
        loop {
            let mut u = None;
            for k in 0..n {
                if !done[k] && dist[k].is_finite() && u.is_none_or(|x: usize| dist[k] < dist[x]) {
                    u = Some(k);
                }
            }
            let u = u?;
            if u == to {
                break;
            }
            done[u] = true;
            for &k in &self.tracks[u].next {
                let d = dist[u] + self.tracks[u].length();
                if !done[k] && d < dist[k] && usable(u, k) {
                    dist[k] = d;
                    prev[k] = u;
                }
            }
        }
        let mut r = vec![to];
        let mut k = to;
        while prev[k] != from {
            k = prev[k];
            r.push(k);
        }
        r.reverse();
        Some(r)
    }

    /// True if every mover is on one and the same track (then the guard is not needed).
    pub(crate) fn all_on_one_track(&self) -> bool {
        let mut k = None;
        for m in &self.movers {
            match (&m.track, k) {
                (None, _) => return false,
                (Some(t), None) => k = Some(t.track),
                (Some(t), Some(x)) if t.track != x => return false,
                _ => {}
            }
        }
        true
    }

    // ------------------------------------------------------------------ part positions (§5.12)

    fn track_part(&self, k: usize) -> Option<usize> {
        let oid = self.tracks[k].part_oid;
        if oid == 0 {
            return None;
        }
        self.parts.iter().position(|p| p.oid == oid)
    }

    /// Position index of track `k`'s part for a link (0 = the part's current index).
    fn track_part_index(&self, k: usize, index: u32) -> u32 {
        match (index, self.track_part(k)) {
            (0, Some(p)) => self.parts[p].index,
            (i, _) => i,
        }
    }

    /// Shift of track `k`'s stored geometry with its part at `index` (0 = current) \[mm\].
    pub(crate) fn track_shift_at(&self, k: usize, index: u32) -> V2 {
        match self.track_part(k) {
            Some(p) => {
                let part = &self.parts[p];
                let i = if index == 0 { part.index } else { index };
                part.positions
                    .get(&i)
                    .map(|q| V2::new(q.x, q.y) - self.tracks[k].geo_origin)
                    .unwrap_or_default()
            }
            None => V2::zeros(),
        }
    }

    /// True if the link `from` end → `to` start is traversable now (§1.6, §5.12): links made
    /// only for specified part positions need exactly those positions; the others need the
    /// two track ends to meet with the parts where they are.
    pub(crate) fn traversable(&self, from: usize, to: usize) -> bool {
        if let Some(&(_, fi, ti)) = self.tracks[from].link_only.iter().find(|x| x.0 == to) {
            return self.track_part_index(from, 0) == fi && self.track_part_index(to, 0) == ti;
        }
        let (a, b) = (&self.tracks[from], &self.tracks[to]);
        match (a.geo.end_pose(), b.geo.start_pose()) {
            (Some(e), Some(st)) => {
                let pe = e.p + self.track_shift_at(from, 0);
                let ps = st.p + self.track_shift_at(to, 0);
                (pe - ps).norm() <= 1e-3
            }
            _ => false,
        }
    }

    // ------------------------------------------------------------------ switches (§5.6.4)

    /// Finds the switches (more than two track ends/starts at one point) and the automatic
    /// collision ranges of their tracks: the arc length from the switch after which the
    /// distance to every other track of the switch exceeds 2R.
    fn rebuild_switches(&mut self) {
        let mut switches: Vec<super::Switch> = Vec::new();
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
                switches.push(super::Switch { incoming, outgoing });
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
    fn switch_occupied(&self, i: usize, w: usize) -> bool {
        let tm = self.movers[i].track.as_ref().expect("on track");
        let my_branch = tm.route.first().copied();
        let sw = &self.switches[w];
        let reach_of = |j: usize| {
            let o = self.movers[j].track.as_ref().expect("on track");
            let (lo, hi) = super::gap::stop_interval(o.v, o.a, o.safe.0, o.safe.1);
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
        i: usize,
        swept: &crate::geometry::ConvexPolygon,
    ) -> Result<(), Rejection> {
        let Some(g) = self.movers[i].group else {
            return Ok(());
        };
        if !self.tracks.iter().any(|t| t.group == Some(g)) {
            return Ok(());
        }
        let own = self.movers[i].track.as_ref().map(|t| t.track);
        let modes = self.track_modes();
        let cs = self.movers[i].cs;
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
            let who = format!("mover '{}'", self.movers[i].name);
            return Err(self.collision(
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
    fn check_track_tubes_free(&mut self, i: usize, tracks: &[usize]) -> Result<(), Rejection> {
        let modes = self.track_modes();
        for &k in tracks {
            let Some(g) = self.tracks[k].group else {
                continue;
            };
            if modes[k] == TrackOperationMode::Moving {
                continue;
            }
            let members = self.groups[g].movers.clone();
            for j in members {
                let o = &self.movers[j];
                if j == i
                    || o.cs != self.tracks[k].cs
                    || o.track.as_ref().is_some_and(|t| tracks.contains(&t.track))
                {
                    continue;
                }
                let area = self.reservation(j);
                if self.tracks[k].tube.iter().any(|q| q.intersects(&area)) {
                    let (oid, name) = (o.oid, o.name.clone());
                    let who = format!("mover '{}'", self.movers[i].name);
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
        Ok(())
    }

    // ------------------------------------------------------------------ virtual axes (§5.8.4)

    fn axis(&self, name: &str) -> Result<usize, Rejection> {
        self.axis_idx
            .get(name)
            .copied()
            .ok_or_else(|| Rejection::unknown_object("axis", name))
    }

    fn axis_move(
        &mut self,
        a: usize,
        who: &str,
        plan: impl FnOnce(
            &crate::motion::Axis1,
        ) -> Result<Profile1, motion_core::trajectory::TrajectoryError>,
    ) -> Result<PlanarReply, Rejection> {
        if !self.axes[a].powered {
            return Err(reject(E_INVALID_STATE, format!("{who}: not powered")));
        }
        let p = plan(&self.axes[a].ax).map_err(|e| traj_err(who, e))?;
        let id = self.new_id();
        let ev_ = &mut self.pending;
        let x = &mut self.axes[a];
        end(ev_, &mut x.cmd, CommandState::Aborted);
        x.ax.start(p);
        x.cmd = Some(id);
        ev(ev_, id, CommandState::Active);
        reply(id, ReplyValue::None)
    }

    /// Advances the virtual axes (before the movers, so slaves see the new master state).
    pub(crate) fn step_axes(&mut self, dt: f64) {
        for x in &mut self.axes {
            if x.ax.advance(dt) {
                end(&mut self.pending, &mut x.cmd, CommandState::Done);
            }
        }
    }

    pub(crate) fn axis_snapshots(&self) -> Vec<crate::snapshot::VirtualAxisSnapshot> {
        self.axes
            .iter()
            .map(|x| crate::snapshot::VirtualAxisSnapshot {
                name: x.name.clone(),
                oid: x.oid,
                powered: x.powered,
                position: x.ax.pos,
                velocity: x.ax.vel,
                acceleration: x.ax.acc,
                busy: x.cmd.is_some(),
            })
            .collect()
    }

    // ------------------------------------------------------------------ gear-in (§5.8)

    /// The master's motion (master coordinates) as a profile, and the time in it that belongs
    /// to the slave's current state: axes and movers before `i` have already advanced this
    /// cycle, movers after it not yet.
    fn master_motion(&self, g: &GearIn, i: usize, dt: f64) -> Option<(Profile1, f64)> {
        let ((p, t), advanced) = match g.master {
            Master::Mover(j) => {
                let mt = self.movers[j].track.as_ref()?;
                let motion = match &mt.plan {
                    Some((mp, t)) => (*mp, *t),
                    None => (Profile1::hold(mt.state()), 0.0),
                };
                (motion, j < i)
            }
            Master::Axis(a) => (self.axes[a].ax.motion(), true),
        };
        let p = if let Master::Mover(_) = g.master {
            p.moved_by(-g.master_origin, 0.0)
        } else {
            p
        };
        if !advanced {
            return Some((p, t));
        }
        Some(if t >= dt {
            (p, t - dt)
        } else {
            // Started this cycle: go back along the start state.
            let s = p.at(t);
            let back = State1 {
                pos: s.pos - s.vel * dt,
                vel: s.vel,
                acc: 0.0,
            };
            (Profile1::hold(back), 0.0)
        })
    }

    /// Route coordinate of the start of track `k` for a mover (None if not on its way).
    fn start_r(&self, tm: &TrackMotion, k: usize) -> Option<f64> {
        if k == tm.track {
            return Some(tm.base);
        }
        let mut r = tm.base + self.tracks[tm.track].length();
        for &x in &tm.route {
            if x == k {
                return Some(r);
            }
            r += self.tracks[x].length();
        }
        None
    }

    #[allow(clippy::too_many_arguments)]
    fn gear_in(
        &mut self,
        i: usize,
        master: Master,
        trail: Vec<usize>,
        (m_sync, mk): (f64, Option<usize>),
        (s_sync, sk): (f64, usize),
        constraint: DynamicConstraint,
        o: super::GearInPosOnTrackWithMasterMoverOptions,
    ) -> Result<PlanarReply, Rejection> {
        let who = format!("mover '{}'", self.movers[i].name);
        finite(&who, "master_sync_position", m_sync)?;
        finite(&who, "slave_sync_position", s_sync)?;
        for (f, v) in [
            ("options.gap", o.gap),
            (
                "options.in_sync_tolerance_distance",
                o.in_sync_tolerance_distance,
            ),
            (
                "options.modulo_tolerance_slave_sync_position",
                o.modulo_tolerance_slave_sync_position,
            ),
            (
                "options.modulo_tolerance_master_sync_position",
                o.modulo_tolerance_master_sync_position,
            ),
        ] {
            if finite(&who, f, v)? < 0.0 {
                return Err(reject(E_INVALID_PARAMETER, format!("{who}: {f} = {v} < 0")));
            }
        }
        self.require_enabled(i, "GearInPosOnTrackWithMasterMover")?;
        self.require_mode(i, CommandKind::GearIn, "GearInPosOnTrackWithMasterMover")?;
        let mt = match master {
            Master::Mover(j) => {
                if i == j {
                    return Err(reject(
                        E_INVALID_PARAMETER,
                        format!("{who}: master = slave"),
                    ));
                }
                let mm = &self.movers[j];
                if mm.sm.state != PlanarState::Enabled {
                    return Err(reject(
                        E_INVALID_STATE,
                        format!("{who}: master '{}' is {:?}", mm.name, mm.sm.state),
                    ));
                }
                let Some(mt) = mm.track.as_ref() else {
                    return Err(reject(
                        E_INVALID_COMMAND_MODE,
                        format!("{who}: master '{}' is not on a track", mm.name),
                    ));
                };
                Some(mt)
            }
            Master::Axis(_) => None,
        };
        let tm = self.movers[i].track.as_ref().expect("OnTrack");
        let cur = tm.track;
        let mut trail = trail;
        if trail.is_empty() {
            trail.push(cur);
            if let (true, Some(mt)) = (o.follow_mover, mt) {
                if mt.track != cur {
                    // The shortest way to the master's track, then the master's path.
                    if let Some(r) = self.route(cur, mt.track) {
                        trail.extend(r);
                    }
                }
                for &k in &mt.route {
                    if !trail.contains(&k) {
                        trail.push(k);
                    }
                }
            }
        }
        let distinct = trail
            .iter()
            .enumerate()
            .all(|(a, x)| !trail[..a].contains(x));
        let contiguous = trail
            .windows(2)
            .all(|w| self.tracks[w[0]].next.contains(&w[1]));
        if trail[0] != cur || !distinct || !contiguous || !trail.contains(&sk) {
            return Err(reject(
                E_TRACKTRAIL_INVALID,
                format!(
                    "{who}: trail {:?} must start with the current track, be contiguous and distinct, and hold the slave sync track",
                    trail.iter().map(|&k| &self.tracks[k].name).collect::<Vec<_>>()
                ),
            ));
        }
        let modes = self.track_modes();
        for &k in &trail {
            if modes[k] == TrackOperationMode::Configuring {
                return Err(reject(
                    E_TRACK_MODE_CONFLICT,
                    format!("{who}: track '{}' is Configuring", self.tracks[k].name),
                ));
            }
        }
        let master_origin = match (mt, mk) {
            (Some(mt), Some(mk)) => match self.start_r(mt, mk) {
                Some(o) => o,
                None => {
                    return Err(reject(
                        E_TARGET_UNREACHABLE,
                        format!(
                            "{who}: the master is not on its way to track '{}'",
                            self.tracks[mk].name
                        ),
                    ))
                }
            },
            _ => 0.0,
        };
        let mut probe = tm.clone();
        probe.route = trail[1..].to_vec();
        let slave_origin = self.start_r(&probe, sk).expect("sync track in the trail");
        let modulo =
            |k: usize, x: f64, now: f64, tol: f64, dir: Direction| -> Result<f64, Rejection> {
                let t = &self.tracks[k];
                if !t.geo.closed() || dir == Direction::NonModulo {
                    return Ok(x);
                }
                modulo_target(x, now, t.length(), tol, dir, 0)
                    .map_err(|_| reject(E_INVALID_PARAMETER, format!("{who}: modulo options")))
            };
        let m_sync = match (mt, mk) {
            (Some(mt), Some(mk)) => modulo(
                mk,
                m_sync,
                mt.r - master_origin,
                o.modulo_tolerance_master_sync_position,
                o.direction_master_sync_position,
            )?,
            _ => m_sync,
        };
        let s_sync = slave_origin
            + modulo(
                sk,
                s_sync,
                tm.r - slave_origin,
                o.modulo_tolerance_slave_sync_position,
                o.direction_slave_sync_position,
            )?;
        let closed = self.tracks[cur].geo.closed();
        let (lo, hi) = if closed {
            (f64::NEG_INFINITY, f64::INFINITY)
        } else {
            let hi = tm.base + trail.iter().map(|&k| self.tracks[k].length()).sum::<f64>();
            (tm.base, hi)
        };
        let m = &self.movers[i];
        let (dyn_, reduced) = Dynamics::resolve(
            &m.cfg.default_dynamics,
            &m.cfg.max_dynamics,
            &constraint,
            &who,
            "constraint",
        )?;
        let id = self.new_id();
        let ev_ = &mut self.pending;
        let m = &mut self.movers[i];
        end(ev_, &mut m.xy_cmd, CommandState::Aborted);
        end(ev_, &mut m.halt_cmd, CommandState::Aborted);
        let tm = m.track.as_mut().expect("OnTrack");
        tm.target = TrackTarget::None;
        tm.route = trail[1..].to_vec();
        tm.gap = o.gap;
        tm.cmd_dyn = dyn_;
        tm.limited = false;
        tm.gear = Some(GearIn {
            master,
            master_origin,
            m_sync,
            s_sync,
            lo,
            hi,
            dyn_,
            tol: o.in_sync_tolerance_distance.max(1e-3),
            allowed: o.allowed_slave_sync_directions,
            follow: o.follow_mover,
            in_sync: false,
            ever_synced: false,
            coupled: false,
            boundary: false,
        });
        m.xy_cmd = Some(id);
        m.guard_stop = false;
        m.warning = if reduced {
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

    /// One cycle of a gear-in: follow the master's path (followMover), compute the target
    /// `s*`, `inSync`, and a fresh time-optimal chase plan to (s* + ṁ·T, ṁ); brake exactly to
    /// the trail boundary when the chase would pass it (§5.8.1).
    fn gear_step(&mut self, i: usize, dt: f64) {
        let Some(tm) = self.movers[i].track.as_ref() else {
            return;
        };
        let Some(g) = tm.gear.as_ref() else {
            return;
        };
        if g.boundary || tm.braking {
            return;
        }
        let Some((mp, t0)) = self.master_motion(g, i, dt) else {
            // The master left its track: the coupling ends.
            let ev_ = &mut self.pending;
            let m = &mut self.movers[i];
            end(ev_, &mut m.xy_cmd, CommandState::Error(E_OBJECT_ERROR));
            let d = m.cfg.default_dynamics;
            if let Some(t) = &mut m.track {
                t.plan_stop(&d);
            }
            return;
        };
        // followMover: the slave's way grows with the master's path.
        let mut extend: Vec<usize> = Vec::new();
        if let (true, Master::Mover(j)) = (g.follow, g.master) {
            let mt = self.movers[j].track.as_ref().expect("master on a track");
            let mut last = *tm.route.last().unwrap_or(&tm.track);
            for k in std::iter::once(mt.track).chain(mt.route.iter().copied()) {
                if k != tm.track
                    && !tm.route.contains(&k)
                    && !extend.contains(&k)
                    && self.tracks[last].next.contains(&k)
                {
                    extend.push(k);
                    last = k;
                }
            }
        }
        // s* = s_sync + (m - m_sync); `mc` is the master at the slave's current time.
        let off = g.s_sync - g.m_sync;
        let mc = mp.at(t0);
        let s_star = off + mc.pos;
        let in_sync = (tm.r - s_star).abs() <= g.tol && (tm.v - mc.vel).abs() <= 0.1;
        let lim = limits_of(&g.dyn_);
        let state = tm.state();
        // Direct coupling (§5.8.1): once the slave is on the law, it follows the master's
        // own motion as long as that stays within the slave's dynamics.
        let mn = mp.at(t0 + dt);
        let eps = 1e-9;
        let within = mn.vel.abs() <= lim.velocity * (1.0 + eps)
            && mn.acc <= lim.acceleration.max(lim.deceleration) * (1.0 + eps)
            && -mn.acc <= lim.acceleration.max(lim.deceleration) * (1.0 + eps);
        let coupled_plan = (mp.moved_by(off, 0.0), t0);
        let vrel = lim.velocity - mc.vel.abs();
        let (mut p, coupled) = if g.coupled && in_sync && within {
            (Some(coupled_plan), true)
        } else if vrel > 1e-6 {
            // Chase: a time-optimal plan to the target, relative to a frame that moves with
            // the master's current velocity (constant over the horizon, §5.8.1), so that the
            // slave arrives on the law with the master's velocity.
            let rel = State1 {
                pos: tm.r - s_star,
                vel: tm.v - mc.vel,
                acc: tm.a,
            };
            let rl = Limits {
                velocity: vrel,
                ..lim
            };
            match Profile1::to_position(rel, 0.0, 0.0, &rl) {
                Ok(q) if q.duration() <= dt + 1e-12 && within => (Some(coupled_plan), true),
                Ok(q) => (Some((q.moved_by(s_star, mc.vel), 0.0)), false),
                Err(_) => (None, false),
            }
        } else {
            // The master is faster than the slave may go: the slave still tries at its
            // limit, no error (§5.8.1; the master may slow down later).
            let v = mc.vel.clamp(-lim.velocity, lim.velocity);
            (
                Profile1::to_velocity(state, v, &lim).ok().map(|q| (q, 0.0)),
                false,
            )
        };
        let predict = |h: f64| {
            let x = mp.at(t0 + h);
            (x.pos, x.vel)
        };
        let d = (g.dyn_.deceleration, g.dyn_.jerk);
        // allowedSlaveSyncDirections restricts the velocity sign until first synchronous.
        if !g.ever_synced {
            if let Some((q, tq)) = &p {
                let c = q.at(tq + dt);
                let wrong = match g.allowed {
                    SyncDirections::Positive => c.vel < -1e-9,
                    SyncDirections::Negative => c.vel > 1e-9,
                    SyncDirections::Both => false,
                };
                if wrong {
                    p = if tm.v == 0.0 && tm.a == 0.0 {
                        None
                    } else {
                        Profile1::stopping(state, &lim).ok().map(|q| (q, 0.0))
                    };
                }
            }
        }
        // Trail boundary: if the master drives the slave out of its trail (the coupled
        // position where the master comes to rest lies outside), brake at the last moment so
        // that the slave stops exactly on the boundary (error follows); a chase transient that
        // would touch the boundary only holds the slave back.
        let mut boundary = false;
        if let Some((q, tq)) = &p {
            let c = q.at(tq + dt);
            let (lo, hi) = reach(c.pos, c.vel, c.acc, d.0, d.1);
            if hi > g.hi + 1e-9 || lo < g.lo - 1e-9 {
                let (m_end, _) = predict(1e9);
                let s_final = off + m_end;
                let beyond = hi > g.hi + 1e-9;
                if (beyond && s_final > g.hi) || (!beyond && s_final < g.lo) {
                    let edge = if beyond { g.hi } else { g.lo };
                    p = Profile1::to_position(state, edge, 0.0, &lim)
                        .or_else(|_| Profile1::stopping(state, &lim))
                        .ok()
                        .map(|q| (q, 0.0));
                    boundary = true;
                } else {
                    p = if tm.v == 0.0 && tm.a == 0.0 {
                        None
                    } else {
                        Profile1::stopping(state, &lim).ok().map(|q| (q, 0.0))
                    };
                }
            }
        }
        let lens: f64 = extend.iter().map(|&k| self.tracks[k].length()).sum();
        let m = &mut self.movers[i];
        let tm = m.track.as_mut().expect("on track");
        tm.route.extend(extend);
        tm.plan = p;
        tm.plan_dyn = tm.cmd_dyn;
        let g = tm.gear.as_mut().expect("gear");
        g.hi += lens;
        g.coupled = coupled && !boundary;
        g.in_sync = in_sync;
        g.ever_synced |= in_sync;
        g.boundary = boundary;
    }

    // ------------------------------------------------------------------ the on-track cycle

    /// Forward / backward limits of the reach of mover `i` (route coordinates): the
    /// neighbours' reach intervals minus / plus its gap (§5.6.3). No alloc, no lock.
    fn gap_limits(&self, i: usize) -> (f64, f64) {
        let tm = self.movers[i].track.as_ref().expect("on track");
        let trk = &self.tracks[tm.track];
        let order = &trk.order;
        let n = order.len();
        let l = trk.length();
        let s = tm.s();
        let rel = |j: usize| {
            let o = self.movers[j].track.as_ref().expect("on track");
            let (lo, hi) = super::gap::stop_interval(o.v, o.a, o.safe.0, o.safe.1);
            (o.s(), lo, hi)
        };
        let mut fwd = f64::INFINITY;
        let mut bwd = f64::NEG_INFINITY;
        if trk.geo.closed() {
            if n > 1 {
                let f = order[(tm.slot + 1) % n];
                let b = order[(tm.slot + n - 1) % n];
                let (sf, lo_f, _) = rel(f);
                fwd = tm.r + (sf - s).rem_euclid(l) + lo_f - tm.gap;
                let (sb, _, hi_b) = rel(b);
                bwd = tm.r - (s - sb).rem_euclid(l) + hi_b + tm.gap;
            }
            return (fwd, bwd);
        }
        if tm.slot + 1 < n {
            let (sf, lo_f, _) = rel(order[tm.slot + 1]);
            fwd = tm.r + (sf - s) + lo_f - tm.gap;
        } else {
            let mut off = l - s;
            for &k in &tm.route {
                if let Some(&f) = self.tracks[k].order.first() {
                    let (sf, lo_f, _) = rel(f);
                    fwd = tm.r + off + sf + lo_f - tm.gap;
                    break;
                }
                off += self.tracks[k].length();
            }
        }
        // §5.6.4: stop at the border of the collision range while another mover (not on our
        // path) occupies the switch at the end of this track.
        if let Some(w) = trk.end_switch {
            let zb = l - trk.range_end;
            if s < zb - 1e-9 && self.switch_occupied(i, w) {
                fwd = fwd.min(tm.r - s + zb);
            }
        }
        if tm.slot > 0 {
            let (sb, _, hi_b) = rel(order[tm.slot - 1]);
            bwd = tm.r - (s - sb) + hi_b + tm.gap;
        } else {
            for &p in &trk.prev {
                if let Some(&b) = self.tracks[p].order.last() {
                    let (sb, _, hi_b) = rel(b);
                    let lp = self.tracks[p].length();
                    bwd = bwd.max(tm.r - s - (lp - sb) + hi_b + tm.gap);
                }
            }
        }
        (fwd, bwd)
    }

    /// A plan of mover `i` towards its command target clamped by the gap limits, checked for
    /// its first cycle; None if only a committed stop is safe.
    fn gap_plan(&self, i: usize, fwd: f64, bwd: f64, dt: f64) -> Option<Profile1> {
        let tm = self.movers[i].track.as_ref()?;
        let TrackTarget::Position(x) = tm.target else {
            return None;
        };
        let d = &tm.cmd_dyn;
        let lim = clamp_target(x, tm.r, fwd, bwd);
        let (lo, hi) = reach(tm.r, tm.v, tm.a, d.deceleration, d.jerk);
        if (x >= tm.r && lim < hi) || (x < tm.r && lim > lo) {
            return None;
        }
        let p = Profile1::to_position(tm.state(), lim, 0.0, &limits_of(d)).ok()?;
        let c = p.at(dt.min(p.duration()));
        let old = reach(tm.r, tm.v, tm.a, tm.safe.0, tm.safe.1);
        let new = reach(c.pos, c.vel, c.acc, d.deceleration, d.jerk);
        step_ok(old, new, fwd, bwd).then_some(p)
    }

    fn brake_plan(tm: &TrackMotion) -> Option<Profile1> {
        let lim = Limits {
            velocity: tm
                .plan_dyn
                .velocity
                .max(tm.cmd_dyn.velocity)
                .max(tm.v.abs()),
            acceleration: tm.plan_dyn.acceleration.max(tm.safe.0),
            deceleration: tm.safe.0,
            jerk: tm.safe.1,
        };
        Profile1::stopping(tm.state(), &lim).ok()
    }

    /// One cycle of an on-track mover: plan, gap control, route transitions, guard, commit.
    pub(crate) fn step_track_mover(
        &mut self,
        i: usize,
        dt: f64,
        grid: &mut Grid,
        cand: &mut Vec<u32>,
    ) {
        let (active, c_moving) = {
            let m = &self.movers[i];
            let tm = m.track.as_ref().expect("on track");
            (tm.active(), m.c.moving())
        };
        if !active && !c_moving {
            self.finish_idle(i);
            return;
        }
        // 0. Gear-in: a fresh chase plan towards the moving target (§5.8.1).
        self.gear_step(i, dt);
        // 1. Plan maintenance: gap checks and re-plans (§5.6.3).
        let needs_limits = {
            let tm = self.movers[i].track.as_ref().expect("on track");
            (tm.plan.is_some() && !tm.braking)
                || (matches!(tm.target, TrackTarget::Position(_))
                    && (tm.plan.is_none() || tm.limited))
        };
        if needs_limits {
            let (fwd, bwd) = self.gap_limits(i);
            let mut replace: Option<(Option<Profile1>, bool)> = None;
            {
                let tm = self.movers[i].track.as_ref().expect("on track");
                if let Some((p, t)) = &tm.plan {
                    if !tm.braking {
                        let c = p.at((t + dt).min(p.duration()));
                        let old = reach(tm.r, tm.v, tm.a, tm.safe.0, tm.safe.1);
                        let d = &tm.plan_dyn;
                        let new = reach(c.pos, c.vel, c.acc, d.deceleration, d.jerk);
                        if !step_ok(old, new, fwd, bwd) {
                            replace = Some((self.gap_plan(i, fwd, bwd, dt), true));
                        }
                    }
                }
                let tm = self.movers[i].track.as_ref().expect("on track");
                if replace.is_none() {
                    if let TrackTarget::Position(x) = tm.target {
                        let lim = clamp_target(x, tm.r, fwd, bwd);
                        let planned_end = tm.plan.as_ref().map(|(p, _)| p.end().pos);
                        let resume = match planned_end {
                            None => {
                                (lim - tm.r).abs() > AT_TARGET
                                    && ((lim - tm.r).abs() > RESUME_MIN || lim == x)
                            }
                            Some(e) => {
                                tm.limited
                                    && tm.since_replan >= REPLAN_CYCLES
                                    && ((lim - e).abs() > REPLAN_MIN || (lim == x && e != x))
                            }
                        };
                        if resume {
                            if let Some(p) = self.gap_plan(i, fwd, bwd, dt) {
                                replace = Some((Some(p), false));
                            }
                        }
                    }
                }
            }
            let m = &mut self.movers[i];
            let tm = m.track.as_mut().expect("on track");
            tm.since_replan = tm.since_replan.saturating_add(1);
            match replace {
                Some((Some(p), _)) => {
                    let end_pos = p.end().pos;
                    tm.plan = Some((p, 0.0));
                    tm.plan_dyn = tm.cmd_dyn;
                    tm.braking = false;
                    tm.limited = match tm.target {
                        TrackTarget::Position(x) => (end_pos - x).abs() > AT_TARGET,
                        TrackTarget::None => false,
                    };
                    tm.since_replan = 0;
                }
                Some((None, true)) => {
                    if let Some(p) = Self::brake_plan(tm) {
                        tm.plan = Some((p, 0.0));
                        tm.braking = true;
                        tm.limited = true;
                        tm.since_replan = 0;
                    }
                }
                _ => {}
            }
            if let Some(tm) = &mut m.track {
                if tm.plan.is_some() && !tm.braking {
                    tm.safe = (tm.plan_dyn.deceleration, tm.plan_dyn.jerk);
                }
            }
        }
        // 2. Next state along the track.
        let m = &self.movers[i];
        let tm = m.track.as_ref().expect("on track");
        let (next, plan_done) = match &tm.plan {
            Some((p, t)) => {
                // A plan that goes on moving after its end (gear-in) never finishes here.
                let endless = p.continues() && p.end().vel != 0.0;
                if !endless && t + dt >= p.duration() - 1e-12 {
                    (p.end(), true)
                } else {
                    (p.at(t + dt), false)
                }
            }
            None => (tm.state(), false),
        };
        let (next, plan_done) = if plan_done {
            (
                State1 {
                    pos: next.pos,
                    vel: 0.0,
                    acc: 0.0,
                },
                true,
            )
        } else {
            (next, false)
        };
        // Route transition (§5.6.5): s passes the end of the current track.
        let mut k = tm.track;
        let mut base = tm.base;
        let mut switch_to: Option<usize> = None;
        if !tm.route.is_empty() && next.pos - base >= self.tracks[k].length() - 1e-12 {
            base += self.tracks[k].length();
            k = tm.route[0];
            switch_to = Some(k);
        }
        let geo = &self.tracks[k].geo;
        let mut pose: TrackPose = geo.pose_at(next.pos - base);
        if self.tracks[k].part_oid != 0 {
            // Tracks move with their part (§1.6).
            pose.p += self.track_shift_at(k, 0);
        }
        let tng = pose.tangent();
        let nrm = V2::new(-tng.y, tng.x);
        let xy_next = Kin2 {
            pos: pose.p,
            vel: tng * next.vel,
            acc: tng * next.acc + nrm * (pose.kappa * next.vel * next.vel),
        };
        let dependent = m.c_mode == CCoordinateMode::Dependent;
        let c_next = if dependent {
            let c = nearest_equivalent(pose.heading_deg(), m.c.pos);
            State1 {
                pos: c,
                vel: (pose.kappa * next.vel).to_degrees(),
                acc: (pose.kappa * next.acc).to_degrees(),
            }
        } else {
            m.c.peek(dt)
        };
        // 3. The no-overlap guard against everything that is not gap-controlled with us.
        if !self.guard_full {
            // All movers are on this one track: gap control separates them; keep a cheap,
            // conservative envelope (square of the diagonal grown by the maximum-dynamics stop
            // distance) for the cycle in which a mover leaves the track.
            let (lo, hi) = crate::motion::stop_range(
                next.vel,
                next.acc,
                m.cfg.max_dynamics.deceleration,
                m.cfg.max_dynamics.jerk,
            );
            let h = m.diag() / 2.0 + lo.abs().max(hi.abs());
            let c = xy_next.pos;
            let env =
                crate::geometry::ConvexPolygon::aabb_box(c - V2::new(h, h), c + V2::new(h, h));
            self.movers[i].envelope = env;
        } else if !m.guard_stop {
            let o = &m.offset;
            let shown = Kin2 {
                pos: xy_next.pos + V2::new(o.pos.x, o.pos.y),
                vel: xy_next.vel,
                acc: xy_next.acc,
            };
            let env = Self::envelope_of(m, &shown, &c_next);
            grid.query(m.cs, &env, cand);
            let my_track = k;
            let blocker = cand.iter().map(|&j| j as usize).find(|&j| {
                if j == i || self.movers[j].cs != m.cs {
                    return false;
                }
                if let Some(o) = &self.movers[j].track {
                    let t = &self.tracks[my_track];
                    if o.track == my_track || t.next.contains(&o.track) || t.prev.contains(&o.track)
                    {
                        return false;
                    }
                }
                env.intersects(&self.movers[j].envelope)
            });
            if let Some(j) = blocker {
                self.track_guard_fire(i, j);
                self.finish_idle(i);
                return;
            }
            grid.insert(m.cs, i as u32, &env);
            self.movers[i].envelope = env;
        }
        // 4. Commit.
        let ev_ = &mut self.pending;
        let m = &mut self.movers[i];
        let tm = m.track.as_mut().expect("on track");
        tm.r = next.pos;
        tm.v = next.vel;
        tm.a = next.acc;
        if let Some((_, t)) = &mut tm.plan {
            *t += dt;
        }
        let old_track = tm.track;
        if let Some(nk) = switch_to {
            tm.track = nk;
            tm.base = base;
            tm.route.remove(0);
        }
        if plan_done {
            tm.plan = None;
            tm.braking = false;
            if tm.gear.as_ref().is_some_and(|g| g.boundary) {
                // §5.8.1: stopped exactly at the trail boundary; the coupling ends in error.
                tm.gear = None;
                end(
                    ev_,
                    &mut m.xy_cmd,
                    CommandState::Error(E_TRACK_BOUNDARY_REACHED),
                );
            }
            let tm = m.track.as_mut().expect("on track");
            if let TrackTarget::Position(x) = tm.target {
                if (tm.r - x).abs() <= AT_TARGET {
                    tm.r = x;
                    tm.target = TrackTarget::None;
                    tm.limited = false;
                    tm.route.clear();
                    end(ev_, &mut m.xy_cmd, CommandState::Done);
                }
            }
        }
        m.xy = xy_next;
        if dependent {
            m.c.pos = c_next.pos;
            m.c.vel = c_next.vel;
            m.c.acc = c_next.acc;
        } else if m.c.advance(dt) {
            end(ev_, &mut m.c_cmd, CommandState::Done);
        }
        if let Some(nk) = switch_to {
            self.tracks[old_track].order.retain(|&x| x != i);
            self.renumber(old_track);
            self.insert_into_order(i, nk);
        }
        self.finish_idle(i);
    }

    /// The guard refuses the next set point of on-track mover `i` because of mover `j`:
    /// the command fails with E_COLLISION and the mover stops along the track (max dynamics).
    fn track_guard_fire(&mut self, i: usize, j: usize) {
        self.last_object_info = PlanarObjectInfo {
            object_type: PlanarObjectType::Mover,
            id: self.movers[j].oid,
        };
        let ev_ = &mut self.pending;
        let m = &mut self.movers[i];
        end(ev_, &mut m.xy_cmd, CommandState::Error(E_COLLISION));
        let mx = m.cfg.max_dynamics;
        if let Some(tm) = &mut m.track {
            tm.plan_stop(&mx);
            tm.safe = (mx.deceleration, mx.jerk);
            tm.braking = true;
        }
        m.guard_stop = true;
    }

    // ------------------------------------------------------------------ snapshots

    pub(crate) fn on_track_snapshot(&self, m: &crate::objects::Mover) -> Option<OnTrackSnapshot> {
        let tm = m.track.as_ref()?;
        let t = &self.tracks[tm.track];
        let s = tm.s();
        Some(OnTrackSnapshot {
            track: t.name.clone(),
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
            gear_master: tm.gear.as_ref().map(|g| match g.master {
                Master::Mover(j) => self.movers[j].name.clone(),
                Master::Axis(a) => self.axes[a].name.clone(),
            }),
        })
    }

    pub(crate) fn track_snapshots(&self) -> Vec<TrackSnapshot> {
        let modes = self.track_modes();
        self.tracks
            .iter()
            .enumerate()
            .map(|(k, t): (usize, &Track)| TrackSnapshot {
                name: t.name.clone(),
                oid: t.oid,
                state: t.sm.state,
                operation_mode: modes[k],
                length: t.length(),
                closed_loop: t.geo.closed(),
                mover_count: t.order.len(),
                movers: t
                    .order
                    .iter()
                    .map(|&j| self.movers[j].name.clone())
                    .collect(),
                previous_tracks: t
                    .prev
                    .iter()
                    .map(|&x| self.tracks[x].name.clone())
                    .collect(),
                subsequent_tracks: t
                    .next
                    .iter()
                    .map(|&x| self.tracks[x].name.clone())
                    .collect(),
                part_oid: t.part_oid,
                collision_range_start: t.range_start,
                collision_range_end: t.range_end,
                collision_range_mode: t.params.range_mode,
                max_mover_width: t.params.max_mover_width,
                max_mover_height: t.params.max_mover_height,
                check_static_collision: t.params.check_static_collision,
                traversable_subsequent_tracks: t
                    .next
                    .iter()
                    .filter(|&&x| self.traversable(k, x))
                    .map(|&x| self.tracks[x].name.clone())
                    .collect(),
            })
            .collect()
    }
}
