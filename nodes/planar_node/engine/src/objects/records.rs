//! The object records: movers, groups, parts and the environment (xplanar.md §1).

use crate::config::{MoverConfig, PartPositionConfig};
use crate::geometry::{ConvexPolygon, V2};
use crate::motion::{stop_range, Axis1, Kin2, PathPlan};
use crate::state::PlanarStateMachine;
use crate::types::{
    CCoordinateMode, CommandMode, ExternalSetpointMode, MoverVector, PlanarObjectInfo,
};
use motion_core::trajectory::State1;
use motion_core::{CmdId, ErrorId};
use std::collections::BTreeMap;

/// One external set point (position, velocity, acceleration).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Setpoint {
    pub pos: MoverVector,
    pub vel: MoverVector,
    pub acc: MoverVector,
}

/// A running external set-point session (§3.2, §5.10).
#[derive(Clone, Debug)]
pub(crate) struct Esg {
    pub mode: ExternalSetpointMode,
    pub session: CmdId,
    /// The Stop command waiting for standstill.
    pub stop_cmd: Option<CmdId>,
    /// Set point for the coming cycle.
    pub pending: Option<Setpoint>,
    /// Last applied set point (for extrapolation).
    pub last: Setpoint,
    /// Consecutive cycles without a set point.
    pub missing: u32,
    /// Absolute mode: braking to rest after Stop/Halt.
    pub stopping: bool,
    /// Stop called after a set point of the same cycle: brake after applying it.
    pub stop_after_pending: bool,
    /// An error detected while accepting a set point, applied in the next cycle.
    pub fault: Option<(ErrorId, String)>,
}

/// MC_PlanarMover.
#[derive(Clone, Debug)]
pub(crate) struct Mover {
    pub name: String,
    pub oid: u32,
    pub cfg: MoverConfig,
    pub sm: PlanarStateMachine,
    /// `objectInfo` of the mover's last E_COLLISION stop (§6.1): the blocking object.
    pub object_info: PlanarObjectInfo,
    /// Command mode while enabled.
    pub mode: CommandMode,
    /// Coordinate system the mover is in.
    pub cs: u32,
    /// Internal XY set point (without relative offsets).
    pub xy: Kin2,
    pub path: Option<PathPlan>,
    pub c: Axis1,
    pub z: Axis1,
    pub a: Axis1,
    pub b: Axis1,
    pub xy_cmd: Option<CmdId>,
    pub c_cmd: Option<CmdId>,
    pub z_cmd: Option<CmdId>,
    pub a_cmd: Option<CmdId>,
    pub b_cmd: Option<CmdId>,
    pub halt_cmd: Option<CmdId>,
    /// Following a collision-guard stop.
    pub guard_stop: bool,
    pub esg: Option<Esg>,
    /// Relative external set-point offsets (pos, vel, acc).
    pub offset: Setpoint,
    pub group: Option<usize>,
    /// Group reservation of the active command (None = standing footprint).
    pub reserved: Option<ConvexPolygon>,
    /// Committed stop envelope (guard).
    pub envelope: ConvexPolygon,
    pub warning: ErrorId,
    pub c_mode: CCoordinateMode,
    /// On-track state (OnTrack / CRotationOnTrack, §5.6).
    pub track: Option<crate::on_track::TrackMotion>,
    /// JoiningTrack: (track, join arc length, C dependent afterwards).
    pub joining: Option<(usize, f64, bool)>,
    /// LeavingTrack: the track left.
    pub leaving: Option<usize>,
}

impl Mover {
    /// Displayed XY state (internal + relative offsets).
    pub fn xy_out(&self) -> Kin2 {
        let o = &self.offset;
        Kin2 {
            pos: self.xy.pos + V2::new(o.pos.x, o.pos.y),
            vel: self.xy.vel + V2::new(o.vel.x, o.vel.y),
            acc: self.xy.acc + V2::new(o.acc.x, o.acc.y),
        }
    }

    pub fn c_out(&self) -> f64 {
        self.c.pos + self.offset.pos.c
    }

    pub fn footprint(&self) -> ConvexPolygon {
        ConvexPolygon::rect(
            self.xy_out().pos,
            self.cfg.width,
            self.cfg.height,
            self.c_out(),
        )
    }

    /// Side of the axis-aligned square that holds the footprint at any c.
    pub fn diag(&self) -> f64 {
        self.cfg.width.hypot(self.cfg.height)
    }

    pub fn square_at(&self, p: V2) -> ConvexPolygon {
        let h = self.diag() / 2.0;
        ConvexPolygon::aabb_box(p - V2::new(h, h), p + V2::new(h, h))
    }

    /// XY stands still (no XY plan, zero velocity, no absolute set points).
    pub fn xy_standing(&self) -> bool {
        self.path.is_none()
            && !self.track.as_ref().is_some_and(|t| t.active())
            && !self.xy.moving()
            && !self
                .esg
                .as_ref()
                .is_some_and(|e| e.mode == ExternalSetpointMode::Absolute)
    }

    /// Nothing moves and nothing will move without a new command.
    pub fn at_rest(&self) -> bool {
        self.xy_standing()
            && !self.c.moving()
            && !self.z.moving()
            && !self.a.moving()
            && !self.b.moving()
            && self.esg.is_none()
    }

    /// Envelope of a mover state: footprint swept along its maximum-dynamics stop (§5.11 guard).
    pub fn stop_envelope(&self, xy: &Kin2, c: &State1) -> ConvexPolygon {
        let c_moves = c.vel != 0.0 || c.acc != 0.0;
        let fp = if c_moves {
            let h = self.diag() / 2.0;
            ConvexPolygon::aabb_box(V2::new(-h, -h), V2::new(h, h))
        } else {
            ConvexPolygon::rect(V2::zeros(), self.cfg.width, self.cfg.height, c.pos)
        };
        if !xy.moving() {
            return if c_moves {
                self.square_at(xy.pos)
            } else {
                ConvexPolygon::rect(xy.pos, self.cfg.width, self.cfg.height, c.pos)
            };
        }
        let u = if xy.vel.norm() > 1e-12 {
            xy.vel.normalize()
        } else {
            xy.acc.normalize()
        };
        let n = V2::new(-u.y, u.x);
        let (d, j) = (
            self.cfg.max_dynamics.deceleration,
            self.cfg.max_dynamics.jerk,
        );
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

    pub fn pose(&self) -> MoverVector {
        let p = self.xy_out().pos;
        let o = &self.offset.pos;
        MoverVector {
            x: p.x,
            y: p.y,
            z: self.z.pos + o.z,
            a: self.a.pos + o.a,
            b: self.b.pos + o.b,
            c: self.c_out(),
        }
    }
}

/// MC_PlanarGroup.
#[derive(Clone, Debug)]
pub(crate) struct Group {
    pub name: String,
    pub oid: u32,
    pub sm: PlanarStateMachine,
    /// Member movers in joining order.
    pub movers: Vec<usize>,
    pub environment: bool,
}

/// A part with its wrapper state (MC_PlanarPart).
#[derive(Clone, Debug)]
pub(crate) struct Part {
    pub name: String,
    pub oid: u32,
    pub tiles: Vec<V2>,
    pub positions: BTreeMap<u32, PartPositionConfig>,
    pub index: u32,
    pub sm: PlanarStateMachine,
    pub initialized: bool,
    pub force_disabled: bool,
    /// ActivatePosition running: (target index, time left, command, movers riding along).
    pub transit: Option<(u32, f64, motion_core::CmdId, Vec<usize>)>,
}

impl Part {
    pub fn origin(&self) -> (u32, V2) {
        let p = self.positions[&self.index];
        (p.cs, V2::new(p.x, p.y))
    }

    pub fn world_tiles_at(&self, index: u32) -> (u32, Vec<V2>) {
        let p = self.positions[&index];
        (
            p.cs,
            self.tiles.iter().map(|t| t + V2::new(p.x, p.y)).collect(),
        )
    }

    /// True if `p` (in `cs`) lies on one of the part's tiles at its current position.
    pub fn contains(&self, cs: u32, p: V2) -> bool {
        let (pcs, o) = self.origin();
        if pcs != cs {
            return false;
        }
        let l = p - o;
        let s = crate::geometry::STATOR_SIDE;
        self.tiles.iter().any(|t| {
            l.x >= t.x - 1e-9 && l.x <= t.x + s + 1e-9 && l.y >= t.y - 1e-9 && l.y <= t.y + s + 1e-9
        })
    }
}

/// MC_PlanarEnvironment.
#[derive(Clone, Debug)]
pub(crate) struct Environment {
    pub name: String,
    pub oid: u32,
    pub processing_unit_oid: u32,
    /// Stators added with AddStator (CS of the plane without parts).
    pub stators: Vec<V2>,
    /// Boundary elements after CreateBoundary.
    pub boundary: Option<usize>,
    pub group: Option<usize>,
}
