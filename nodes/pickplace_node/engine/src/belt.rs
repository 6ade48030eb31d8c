//! Simulated conveyor belts, belt frames and workpiece tracking (pick_and_place.md §2.2, §7.1,
//! §13, §14).

use crate::geometry::Vec3;
use crate::params::ConveyorBeltPar;
use nalgebra::Rotation3;
use serde::{Deserialize, Serialize};

/// Maximum number of tracked workpieces per belt (pending + visible, §14).
pub const MAX_WORKPIECES_PER_BELT: usize = 30;

/// A simulated belt axis: velocity ramps to the commanded value with the commanded acceleration;
/// the position is integrated every cycle before the TM step (§2.2).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BeltAxis {
    /// Belt position s_i [units].
    pub position: f64,
    /// Belt velocity [units/s].
    pub velocity: f64,
    /// Commanded velocity [units/s].
    pub target_velocity: f64,
    /// Ramp acceleration [units/s²]; 0 = jump.
    pub acceleration: f64,
}

impl BeltAxis {
    /// Integrates one cycle (trapezoidal rule, exact for constant acceleration).
    pub fn step(&mut self, dt: f64) {
        let v0 = self.velocity;
        let dv = self.target_velocity - v0;
        let v1 = if self.acceleration <= 0.0 || dv.abs() <= self.acceleration * dt {
            self.target_velocity
        } else {
            v0 + self.acceleration * dt * dv.signum()
        };
        self.position += 0.5 * (v0 + v1) * dt;
        self.velocity = v1;
    }
}

/// The belt coordinate system in MCS: p_mcs = O + R·p_b, R = Rz(C)·Ry(B)·Rx(A) (§7.1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BeltFrame {
    /// Origin O in MCS.
    pub origin: Vec3,
    /// Rotation R.
    pub rotation: Rotation3<f64>,
}

impl BeltFrame {
    /// The frame of `alrConveyorBeltOrigin`.
    pub fn from_par(par: &ConveyorBeltPar) -> Self {
        let o = &par.conveyor_belt_origin;
        let (a, b, c) = (o[3].to_radians(), o[4].to_radians(), o[5].to_radians());
        let rotation = Rotation3::from_axis_angle(&Vec3::z_axis(), c)
            * Rotation3::from_axis_angle(&Vec3::y_axis(), b)
            * Rotation3::from_axis_angle(&Vec3::x_axis(), a);
        BeltFrame {
            origin: Vec3::new(o[0], o[1], o[2]),
            rotation,
        }
    }
    /// MCS position of a point given in belt coordinates.
    pub fn to_mcs(&self, p_b: Vec3) -> Vec3 {
        self.origin + self.rotation * p_b
    }
    /// Running direction R·(1, 0, 0) in MCS.
    pub fn direction(&self) -> Vec3 {
        self.rotation * Vec3::x()
    }
    /// The belt's Z axis R·(0, 0, 1) in MCS ("above" for IP1/IP2 on this belt).
    pub fn up(&self) -> Vec3 {
        self.rotation * Vec3::z()
    }
}

/// Tracking state of a workpiece (§14).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WorkpieceState {
    /// Receive edge seen, coordinates not yet valid.
    Pending,
    /// Coordinates valid: the PCS exists.
    Visible,
}

/// One tracked workpiece on a belt.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Workpiece {
    /// Unique id (per engine, ascending by receive time).
    pub id: u64,
    /// Belt position latched at the receive edge [units].
    pub s_receive: f64,
    /// `ascInitialObjectPosition` (valid at the receive edge), belt coordinates.
    pub initial: [f64; 6],
    /// Pending or visible.
    pub state: WorkpieceState,
    /// Reserved as the target of a planned profile (not eligible for another one).
    pub reserved: bool,
}

impl Workpiece {
    /// Position in belt coordinates at belt position `s`: p0 + (s − s_rx, 0, 0).
    pub fn belt_position(&self, s: f64) -> Vec3 {
        Vec3::new(
            self.initial[0] + (s - self.s_receive),
            self.initial[1],
            self.initial[2],
        )
    }
}

/// One belt: its axis, parameters, inputs (`ascBeltInput[i]`) and tracked workpieces.
#[derive(Clone, Debug, Default)]
pub struct Belt {
    /// Simulated belt axis.
    pub axis: BeltAxis,
    /// `ascConveyorBeltPar[i]`.
    pub par: ConveyorBeltPar,
    /// Tracked workpieces, in receive order (FIFO).
    pub workpieces: Vec<Workpiece>,
    /// Level of `xWorkpieceOnBeltReceive`.
    pub receive: bool,
    /// Level of `xValidPos`.
    pub valid_pos: bool,
    /// `ascInitialObjectPosition`.
    pub initial_object_position: [f64; 6],
    /// `lrAux1TargetPos` of this belt.
    pub aux1_target_pos: f64,
    pub(crate) prev_receive: bool,
    pub(crate) prev_valid_pos: bool,
}

/// What happened to a workpiece in a cycle (§18 `~/events`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum WorkpieceEventKind {
    /// Registered by a receive edge.
    Received,
    /// Coordinates taken over (PCS created).
    Visible,
    /// Reached by the TCP as a pick target.
    Picked,
    /// Reached by the TCP as a place target.
    Placed,
    /// Left the working area before it was served; deleted.
    Missed,
    /// Receive edge ignored: 30 workpieces tracked.
    Rejected,
}

impl Belt {
    /// The belt frame.
    pub fn frame(&self) -> BeltFrame {
        BeltFrame::from_par(&self.par)
    }

    /// MCS position of a workpiece now.
    pub fn workpiece_mcs(&self, wp: &Workpiece) -> Vec3 {
        self.frame().to_mcs(wp.belt_position(self.axis.position))
    }

    /// Evaluates the receive/valid edges of this cycle (§14). Returns (kind, id) events and
    /// whether the maximum was reached with this cycle's receive edge (warning 17918).
    pub fn detect(
        &mut self,
        next_id: &mut u64,
        events: &mut Vec<(WorkpieceEventKind, u64)>,
    ) -> bool {
        let mut max_reached = false;
        if self.receive && !self.prev_receive {
            if self.workpieces.len() >= MAX_WORKPIECES_PER_BELT {
                events.push((WorkpieceEventKind::Rejected, 0));
                max_reached = true;
            } else {
                *next_id += 1;
                self.workpieces.push(Workpiece {
                    id: *next_id,
                    s_receive: self.axis.position,
                    initial: [0.0; 6],
                    state: WorkpieceState::Pending,
                    reserved: false,
                });
                events.push((WorkpieceEventKind::Received, *next_id));
                if self.workpieces.len() == MAX_WORKPIECES_PER_BELT {
                    max_reached = true;
                }
            }
        }
        if self.valid_pos && !self.prev_valid_pos {
            // Completes the oldest pending entry (FIFO).
            if let Some(wp) = self
                .workpieces
                .iter_mut()
                .find(|w| w.state == WorkpieceState::Pending)
            {
                wp.initial = self.initial_object_position;
                wp.state = WorkpieceState::Visible;
                events.push((WorkpieceEventKind::Visible, wp.id));
            }
        }
        self.prev_receive = self.receive;
        self.prev_valid_pos = self.valid_pos;
        max_reached
    }

    /// Belt X of a workpiece now.
    pub fn belt_x(&self, wp: &Workpiece) -> f64 {
        wp.belt_position(self.axis.position).x
    }

    /// Deletes visible, unreserved workpieces beyond the upper sync limit ("order came too
    /// late", §14); returns their ids.
    pub fn delete_missed(&mut self, missed: &mut Vec<u64>) {
        if !self.par.is_configured() {
            return;
        }
        let s = self.axis.position;
        let upper = self.par.upper_sync_limit;
        self.workpieces.retain(|w| {
            let gone =
                w.state == WorkpieceState::Visible && !w.reserved && w.belt_position(s).x > upper;
            if gone {
                missed.push(w.id);
            }
            !gone
        });
    }
}
