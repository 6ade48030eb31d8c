//! Track Pick & Place engine (`L_TT1P_TrackPickAndPlaceBase`, pick_and_place.md): a pure,
//! deterministic simulation of the technology module driving an axis group with a gripper that
//! picks workpieces from, and places them on, moving conveyor belts.
//!
//! Drive it with [`PickPlaceEngine::command`] (levels, pulses, parameter writes, simulation
//! hooks; [`PickPlaceCommand`]) and [`PickPlaceEngine::step`] (one cycle); read
//! [`PickPlaceSnapshot`] and drain [`CellEvent`]s. No I/O, clock or threads.
//!
//! ```
//! use motion_core::{Engine, Tick};
//! use pickplace_engine::{PickPlaceCommand, PickPlaceConfig, PickPlaceEngine, TmState};
//!
//! let mut cfg = PickPlaceConfig::default();
//! cfg.params.path_vel = 100.0;
//! cfg.params.max_vel = [0.0; 7]; // no axis limits on the path
//! cfg.params.target_pos = [50.0, 0.0, 0.0, 180.0, 0.0, 0.0, 0.0];
//! let mut cell = PickPlaceEngine::new(cfg).unwrap();
//! cell.command(PickPlaceCommand::SetEnable(true)).unwrap();
//! cell.command(PickPlaceCommand::SetRegulatorOn(true)).unwrap();
//! let id = cell.command(PickPlaceCommand::Execute { set_target: 0 }).unwrap();
//! let mut events = Vec::new();
//! for index in 0..5000 {
//!     cell.step(Tick { index, dt: 0.001 }, &mut events);
//! }
//! let s = cell.snapshot();
//! assert_eq!(s.state, TmState::Ready);
//! assert!(s.outputs.done);
//! assert!((s.tcp[0] - 50.0).abs() < 1e-9);
//! assert!(events.iter().any(|e| e.id == id));
//! ```
//!
//! Modules follow the spec: [`params`] (§3.4, §3.5), [`config`] (§2, §8, §18), [`geometry`]
//! (§7), [`path_run`] (§7.7, §7.8, §9, §12, §15.1), [`belt`] (§2.2, §13, §14),
//! [`engine`] (§2.3, §4 – §6, §8 – §11, §15, §16).

// Axis arrays are indexed by the manual's axis numbers; index loops read like the spec.
#![allow(clippy::needless_range_loop)]

pub mod axis_limits;
pub mod belt;
pub mod command;
pub mod config;
pub mod engine;
pub mod error_ids;
pub mod geometry;
pub mod kinematics;
pub mod params;
pub mod path_run;
pub mod snapshot;
pub mod state;

pub use command::{FaultKind, PickPlaceCommand, ServiceRequest, StopInputs};
pub use config::{AxisConfig, BeltConfig, PickPlaceConfig};
pub use engine::PickPlaceEngine;
pub use params::{ConveyorBeltPar, ScPar};
pub use snapshot::{CellEvent, GripperEvent, Outputs, PickPlaceSnapshot};
pub use state::TmState;
