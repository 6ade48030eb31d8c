//! The runtime every node uses: the cyclic controller (`cycle`), its ROS time (`clock`), its
//! statistics (`stats`),
//! real-time helpers (`rt`), and the shared ROS 2 shell (`shell`: node creation on loopback,
//! services and actions with the PLCopen handshake, parameters, /diagnostics, /clock, rosout).

pub mod clock;
pub mod cycle;
pub mod failsafe;
pub mod live;
mod page;
pub mod record;
pub mod ros_args;
pub mod rt;
pub mod signals;
pub mod stats;

pub use cycle::{
    ClockMode, Controller, ControllerHandle, CycleConfig, ScriptedCommand, Stamped, TimedEvent,
};
pub use stats::CycleStats;
pub mod logging;
pub mod shell;

pub use shell::{ActionBinding, CommandLabel, NodeShell, ShellError, ShellSettings};
pub mod host;

pub use host::{CommonConfig, ConfigError, NodeHost};
pub mod launch;

pub use launch::{NodeKind, RunningNode, StartError};
