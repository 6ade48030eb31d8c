//! [`TrackSystem`]: the track subsystem's own state (tracks, switches, virtual axes) and its
//! behaviour: track methods (§3.3), JoinTrack / LeaveTrack / MoveOnTrack /
//! AdoptTrackOrientation (§3.2), operation modes (§2.5), and the on-track cycle with gap
//! control (§5.6.3) and network transitions (§5.6.5). Each concept has its module below.
//! The movers it drives are handed in as `objects: &mut dyn MoverDrive` (module doc of `track`).

use super::drive::{end, ev, started, traj_err, Mover, MoverDrive};
use super::gap::{reach, step_ok, AIM_INSIDE, GAP_EPS};
use super::geometry::{GeometryError, TrackPose};
use super::{GearIn, Master, SyncDirections, Track, TrackMotion, TrackOperationMode, TrackTarget};
use crate::admission::CommandKind;
use crate::command::PlanarCommand;
use crate::errors::*;
use crate::geometry::V2;
use crate::guard::Grid;
use crate::motion::{in_c_window, modulo_target, Kin2};
use crate::snapshot::{OnTrackSnapshot, PlanarReply, ReplyValue, TrackSnapshot};
use crate::types::*;
use motion_core::refill::{refill_vec, reuse_opt_str, reuse_str, reuse_strs};
use motion_core::trajectory::{Limits, Profile1, State1};
use motion_core::{CmdId, CommandState, ErrorId, Rejection};
use std::collections::HashMap;

mod cycle;
mod gear_in;
mod membership;
mod ride;
mod snapshots;
mod switches;

/// The track subsystem's state: tracks in configuration order (§1.6), the switches of the
/// network (§5.6.4, rebuilt after geometry and link changes) and the virtual master axes
/// (§5.8.4).
#[derive(Default)]
pub struct TrackSystem {
    pub(crate) tracks: Vec<Track>,
    pub(crate) track_idx: HashMap<String, usize>,
    pub(crate) switches: Vec<super::Switch>,
    pub(crate) axes: Vec<super::VirtualAxis>,
    pub(crate) axis_idx: HashMap<String, usize>,
}

impl TrackSystem {
    /// The configured tracks (without their init parameters, which `build::tracks` applies as
    /// commands) and virtual axes; tracks on parts start where their part is.
    pub(crate) fn new(cfg: &crate::config::PlanarConfig, objects: &dyn MoverDrive) -> Self {
        let part_frames: Vec<super::PartFrame> = (objects.parts().iter())
            .map(|p| {
                let (cs, origin) = p.origin();
                super::PartFrame {
                    oid: p.oid,
                    cs,
                    origin,
                }
            })
            .collect();
        let (tracks, track_idx) = super::build_tracks(cfg, &part_frames);
        let (axes, axis_idx) = super::build_axes(cfg);
        TrackSystem {
            tracks,
            track_idx,
            switches: Vec::new(),
            axes,
            axis_idx,
        }
    }
}

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

impl TrackSystem {
    /// GetPositionAt without a command: the pose at `arc_length` in the track's current part
    /// position. Pure, so the shell can sample whole tracks through the runtime's read-only
    /// query path (drawing markers must not flood `~/command_status`).
    pub(crate) fn track_position_at(
        &self,
        objects: &dyn MoverDrive,
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
        p.p += self.track_shift_at(objects, k, 0);
        let refid = if objects.coordinate_system_count() == 1 && t.cs == 0 {
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
    pub(crate) fn track_modes(&self, objects: &dyn MoverDrive) -> Vec<TrackOperationMode> {
        let mut moving = vec![false; self.tracks.len()];
        let mut config = vec![false; self.tracks.len()];
        for m in objects.movers() {
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

    fn require_track_ready(
        &self,
        objects: &dyn MoverDrive,
        k: usize,
        who: &str,
    ) -> Result<TrackOperationMode, Rejection> {
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
        Ok(self.track_modes(objects)[k])
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
    fn track_point(
        &self,
        objects: &dyn MoverDrive,
        k: usize,
        field: &str,
        p: &PositionXYC,
    ) -> Result<V2, Rejection> {
        let who = self.track_who(k);
        p.check_finite(&who, field)?;
        let (cs, v) = objects.resolve(&who, p.x, p.y, p.reference_id)?;
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
        Ok(v - self.track_shift_at(objects, k, 0))
    }

    fn link(&mut self, from: usize, to: usize) {
        if !self.tracks[from].next.contains(&to) {
            self.tracks[from].next.push(to);
        }
        if !self.tracks[to].prev.contains(&from) {
            self.tracks[to].prev.push(from);
        }
    }

    fn check_position_index(
        &self,
        objects: &dyn MoverDrive,
        k: usize,
        index: u32,
        which: &str,
    ) -> Result<(), Rejection> {
        if index == 0 {
            return Ok(());
        }
        let t = &self.tracks[k];
        let ok = objects
            .parts()
            .iter()
            .find(|p| p.oid == t.part_oid)
            .or(objects.parts().first().filter(|_| t.part_oid == 0))
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
        objects: &mut dyn MoverDrive,
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
        let delta = self.track_shift_at(objects, o, adv.other_track_part_position_index)
            - self.track_shift_at(objects, k, adv.this_track_part_position_index);
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
                self.track_part_index(objects, o, adv.other_track_part_position_index),
                self.track_part_index(objects, k, adv.this_track_part_position_index),
            );
            self.tracks[o].link_only.push((k, fi, ti));
        }
        objects.done_now()
    }

    fn end_at_track(
        &mut self,
        objects: &mut dyn MoverDrive,
        k: usize,
        o: usize,
        adv: super::TrackLinkAdvancedOptions,
    ) -> Result<PlanarReply, Rejection> {
        let who = self.track_who(k);
        self.require_disabled_track(k)?;
        let delta = self.track_shift_at(objects, o, adv.other_track_part_position_index)
            - self.track_shift_at(objects, k, adv.this_track_part_position_index);
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
                self.track_part_index(objects, k, adv.this_track_part_position_index),
                self.track_part_index(objects, o, adv.other_track_part_position_index),
            );
            self.tracks[k].link_only.push((o, fi, ti));
        }
        objects.done_now()
    }

    fn track_clear(
        &mut self,
        objects: &mut dyn MoverDrive,
        k: usize,
    ) -> Result<PlanarReply, Rejection> {
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
        objects.done_now()
    }

    fn track_enable(
        &mut self,
        objects: &mut dyn MoverDrive,
        k: usize,
    ) -> Result<PlanarReply, Rejection> {
        let who = self.track_who(k);
        let t = &self.tracks[k];
        if t.sm.state == PlanarState::Disabled {
            if t.geo.length() <= 0.0 {
                return Err(reject(
                    E_GEOMETRY_INVALID,
                    format!("{who}: Enable without geometry"),
                ));
            }
            if objects.parts().len() > 1 && t.part_oid == 0 {
                return Err(reject(
                    E_GEOMETRY_INVALID,
                    format!("{who}: PartOID missing with more than one part"),
                ));
            }
            self.track_lies_on_part(objects, k)?;
        }
        let id = objects.new_id();
        let timing = objects.timing();
        let r = self.tracks[k]
            .sm
            .enable(id, &timing, &who, objects.events())?;
        ev(
            objects.events(),
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
    pub(crate) fn track_lies_on_part(
        &self,
        objects: &dyn MoverDrive,
        k: usize,
    ) -> Result<(), Rejection> {
        let who = self.track_who(k);
        let t = &self.tracks[k];
        let part = if t.part_oid != 0 {
            objects.parts().iter().find(|p| p.oid == t.part_oid)
        } else {
            objects.parts().first()
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
            let shift = self.track_shift_at(objects, k, 0);
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

    fn track_disable(
        &mut self,
        objects: &mut dyn MoverDrive,
        k: usize,
    ) -> Result<PlanarReply, Rejection> {
        if !self.tracks[k].order.is_empty()
            || objects
                .movers()
                .iter()
                .any(|m| m.joining.is_some_and(|j| j.0 == k) || m.leaving == Some(k))
        {
            return Err(reject(
                E_INVALID_STATE,
                format!("{}: Disable with movers on the track", self.track_who(k)),
            ));
        }
        let id = objects.new_id();
        let timing = objects.timing();
        let r = self.tracks[k].sm.disable(id, &timing, objects.events());
        ev(
            objects.events(),
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
    pub(crate) fn step_tracks(&mut self, objects: &mut dyn MoverDrive, dt: f64) {
        for t in &mut self.tracks {
            if t.sm.advance(dt, true).is_some() {
                t.sm.complete(objects.events());
            }
        }
    }

    /// Dispatch of the track commands and the on-track mover methods.
    pub(crate) fn track_command(
        &mut self,
        objects: &mut dyn MoverDrive,
        cmd: PlanarCommand,
    ) -> Result<PlanarReply, Rejection> {
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
                self.tracks[k].geo_origin =
                    self.track_shift_at(objects, k, 0) + self.tracks[k].geo_origin;
            }
        }
        let r = self.track_command_inner(objects, cmd);
        if geometry && r.is_ok() {
            self.rebuild_switches();
        }
        r
    }

    fn track_command_inner(
        &mut self,
        objects: &mut dyn MoverDrive,
        cmd: PlanarCommand,
    ) -> Result<PlanarReply, Rejection> {
        use PlanarCommand as C;
        match cmd {
            C::JoinTrack {
                mover,
                track,
                constraint,
                options,
            } => {
                let i = objects.mover(&mover)?;
                let k = self.track(&track)?;
                self.join_track(objects, i, k, constraint, options)
            }
            C::LeaveTrack {
                mover,
                target_position,
                constraint,
                options,
            } => {
                let i = objects.mover(&mover)?;
                self.leave_track(objects, i, target_position, constraint, options)
            }
            C::MoveOnTrack {
                mover,
                track,
                target_position,
                constraint,
                options,
            } => {
                let i = objects.mover(&mover)?;
                let k = if track.is_empty() {
                    None
                } else {
                    Some(self.track(&track)?)
                };
                self.move_on_track(objects, i, k, target_position, constraint, options)
            }
            C::AdoptTrackOrientation {
                mover,
                constraint,
                options,
            } => {
                let i = objects.mover(&mover)?;
                self.adopt_track_orientation(objects, i, constraint, options)
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
                let i = objects.mover(&mover)?;
                let j = objects.mover(&master_mover)?;
                let trail = track_trail
                    .iter()
                    .map(|t| self.track(t))
                    .collect::<Result<Vec<_>, _>>()?;
                let mk = self.track(&master_sync_position_track)?;
                let sk = self.track(&slave_sync_position_track)?;
                self.gear_in(
                    objects,
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
                let i = objects.mover(&mover)?;
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
                    objects,
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
                    let ev_ = objects.events();
                    end(ev_, &mut self.axes[a].cmd, CommandState::Aborted);
                }
                self.axes[a].powered = enable;
                objects.done_now()
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
                self.axis_move(objects, a, &who, |ax| ax.plan_to(position, &d))
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
                self.axis_move(objects, a, &who, |ax| ax.plan_stop(&d))
            }
            C::TrackAppendPosition { track, position } => {
                let k = self.track(&track)?;
                let p = self.track_point(objects, k, "position", &position)?;
                self.require_disabled_track(k)?;
                self.require_unlocked(k)?;
                let who = self.track_who(k);
                self.tracks[k]
                    .geo
                    .append_position(p, position.c.to_radians())
                    .map_err(|e| geo_err(&who, e))?;
                objects.done_now()
            }
            C::TrackAppendLine { track, start, end } => {
                let k = self.track(&track)?;
                let a = self.track_point(objects, k, "start", &start)?;
                let b = self.track_point(objects, k, "end", &end)?;
                self.require_disabled_track(k)?;
                self.require_unlocked(k)?;
                let who = self.track_who(k);
                let mut g = self.tracks[k].geo.clone();
                g.append_line(a, b).map_err(|e| geo_err(&who, e))?;
                self.tracks[k].geo = g;
                objects.done_now()
            }
            C::TrackAppendCircle {
                track,
                start,
                end,
                center,
                clockwise,
            } => {
                let k = self.track(&track)?;
                let a = self.track_point(objects, k, "start", &start)?;
                let b = self.track_point(objects, k, "end", &end)?;
                let c = self.track_point(objects, k, "center", &center)?;
                self.require_disabled_track(k)?;
                self.require_unlocked(k)?;
                let who = self.track_who(k);
                let mut g = self.tracks[k].geo.clone();
                g.append_circle(a, b, c, clockwise)
                    .map_err(|e| geo_err(&who, e))?;
                self.tracks[k].geo = g;
                objects.done_now()
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
                objects.done_now()
            }
            C::TrackStartFromTrack { track, other } => {
                let k = self.track(&track)?;
                let o = self.track(&other)?;
                self.start_from_track(objects, k, o, Default::default())
            }
            C::TrackEndAtTrack { track, other } => {
                let k = self.track(&track)?;
                let o = self.track(&other)?;
                self.end_at_track(objects, k, o, Default::default())
            }
            C::TrackStartFromTrackAdvanced {
                track,
                other,
                options,
            } => {
                let k = self.track(&track)?;
                let o = self.track(&other)?;
                self.check_position_index(
                    objects,
                    k,
                    options.this_track_part_position_index,
                    "this",
                )?;
                self.check_position_index(
                    objects,
                    o,
                    options.other_track_part_position_index,
                    "other",
                )?;
                self.start_from_track(objects, k, o, options)
            }
            C::TrackEndAtTrackAdvanced {
                track,
                other,
                options,
            } => {
                let k = self.track(&track)?;
                let o = self.track(&other)?;
                self.check_position_index(
                    objects,
                    k,
                    options.this_track_part_position_index,
                    "this",
                )?;
                self.check_position_index(
                    objects,
                    o,
                    options.other_track_part_position_index,
                    "other",
                )?;
                self.end_at_track(objects, k, o, options)
            }
            C::TrackClear { track } => {
                let k = self.track(&track)?;
                self.track_clear(objects, k)
            }
            C::TrackEnable { track } => {
                let k = self.track(&track)?;
                self.track_enable(objects, k)
            }
            C::TrackDisable { track } => {
                let k = self.track(&track)?;
                self.track_disable(objects, k)
            }
            C::TrackReset { track } => {
                let k = self.track(&track)?;
                let who = self.track_who(k);
                let id = objects.new_id();
                let timing = objects.timing();
                let r = self.tracks[k].sm.reset(id, &timing, &who)?;
                ev(
                    objects.events(),
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
                let g = objects.group(&group)?;
                let who = self.track_who(k);
                if objects.groups()[g].sm.state != PlanarState::Enabled {
                    return Err(reject(
                        E_GROUP_NOT_READY,
                        format!(
                            "{who}: group '{group}' is {:?}",
                            objects.groups()[g].sm.state
                        ),
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
                        format!(
                            "{who}: already member of group '{}'",
                            objects.groups()[og].name
                        ),
                    ));
                }
                let tube = self.tracks[k].build_tube();
                self.track_static_check(objects, k, g, &tube)?;
                self.tracks[k].tube = tube;
                self.tracks[k].group = Some(g);
                objects.done_now()
            }
            C::TrackRemoveFromGroup { track } => {
                let k = self.track(&track)?;
                self.tracks[k].group = None;
                self.tracks[k].tube.clear();
                objects.done_now()
            }
            C::TrackGetLength { track } => {
                let k = self.track(&track)?;
                let id = objects.new_id();
                ev(objects.events(), id, CommandState::Done);
                reply(id, ReplyValue::Scalar(self.tracks[k].length()))
            }
            C::TrackGetArcLengthClosestTo { track, point } => {
                let k = self.track(&track)?;
                let p = self.track_point(objects, k, "point", &point)?;
                if self.tracks[k].geo.is_empty() {
                    return Err(reject(
                        E_INVALID_STATE,
                        format!("{}: no geometry", self.track_who(k)),
                    ));
                }
                let s = self.tracks[k].geo.closest(p);
                // (`p` is already in stored coordinates: track_point subtracted the shift.)
                let id = objects.new_id();
                ev(objects.events(), id, CommandState::Done);
                reply(id, ReplyValue::Scalar(s))
            }
            C::TrackGetPositionAt { track, arc_length } => {
                let p = self.track_position_at(objects, &track, arc_length)?;
                let id = objects.new_id();
                ev(objects.events(), id, CommandState::Done);
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
                self.track_set_init_parameters(objects, k, &cfg)
            }
            C::TrackGetPlanarObjectInfo { track } => {
                let k = self.track(&track)?;
                let id = objects.new_id();
                ev(objects.events(), id, CommandState::Done);
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
}

/// What the objects reach through `TrackHooks` (wired in `crate::engine`) beyond the
/// concept modules: part moves, injected errors, names.
impl TrackSystem {
    /// The part with `part_oid` moved into coordinate system `cs`: its tracks go with it (§1.6).
    pub(crate) fn part_moved(&mut self, part_oid: u32, cs: u32) {
        for t in self.tracks.iter_mut().filter(|t| t.part_oid == part_oid) {
            t.cs = cs;
        }
    }

    /// InjectError on the named track (§1.5 simulation).
    pub(crate) fn inject_error(
        &mut self,
        name: &str,
        reaction: ErrorReaction,
        timing: &crate::state::Timing,
        events: &mut Vec<motion_core::CommandEvent>,
    ) -> Result<(), Rejection> {
        let k = self.track(name)?;
        self.tracks[k]
            .sm
            .error(E_OBJECT_ERROR, reaction, timing, events);
        Ok(())
    }

    pub(crate) fn track_name(&self, k: usize) -> &str {
        &self.tracks[k].name
    }

    /// The names of the tracks that are members of group `g`, in `old`'s buffers.
    pub(crate) fn group_tracks(&self, g: usize, old: Vec<String>) -> Vec<String> {
        let members = self.tracks.iter().filter(|t| t.group == Some(g));
        reuse_strs(old, members.map(|t| t.name.as_str()))
    }
}
