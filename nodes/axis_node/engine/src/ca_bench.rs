//! Benchmark and test setups: axes with the common settings of collision_avoidance.md §10 and
//! a moving ring of `n` movers ([`bench_ring`]).

use crate::ca::*;
use crate::command::{AxisCommand, BufferMode, Power};
use crate::config::AxisConfig;
use crate::engine::AxisEngine;
use motion_core::{Engine, Tick};

/// Axis settings of §10: maxima V 2000, A/D 20000, J 200000 (`max_velocity`,
/// `fast_acceleration/deceleration/jerk`); defaults A/D 10000, J 100000; start at `position`.
pub fn ca_axis_config(position: f64) -> AxisConfig {
    AxisConfig {
        initial_position: position,
        max_velocity: 2000.0,
        acceleration: 10000.0,
        deceleration: 10000.0,
        jerk: 100000.0,
        fast_acceleration: 20000.0,
        fast_deceleration: 20000.0,
        fast_jerk: 200000.0,
        en_position_lag_monitoring: false,
        ..AxisConfig::default()
    }
}

/// An engine with one axis per `(name, position)`, all powered (one cycle of `dt` stepped),
/// in one CA group `group` with `cfg` (idents 1, 2, … in list order), enabled.
pub fn ca_engine(
    movers: &[(String, f64)],
    group: &str,
    cfg: CaGroupConfig,
    dt: f64,
) -> Result<AxisEngine, motion_core::Rejection> {
    let axes: Vec<(String, AxisConfig)> = movers
        .iter()
        .map(|(n, x)| (n.clone(), ca_axis_config(*x)))
        .collect();
    ca_engine_with(&axes, group, cfg, dt)
}

/// [`ca_engine`] with an own configuration per axis (e.g. unequal maxima).
pub fn ca_engine_with(
    movers: &[(String, AxisConfig)],
    group: &str,
    cfg: CaGroupConfig,
    dt: f64,
) -> Result<AxisEngine, motion_core::Rejection> {
    let mut e = AxisEngine::new(movers.to_vec())?;
    e.add_ca_group(group, cfg)?;
    for (n, _) in movers {
        e.command(AxisCommand::Power(Power {
            axis: n.clone(),
            enable: true,
            enable_positive: true,
            enable_negative: true,
            override_percent: 100.0,
            buffer_mode: BufferMode::Aborting,
        }))?;
    }
    let mut ev = Vec::new();
    e.step(Tick { index: 0, dt }, &mut ev);
    for (i, (n, _)) in movers.iter().enumerate() {
        e.command(AxisCommand::Ca(CaCommand::AddAxisToGroup {
            group: group.into(),
            axis: n.clone(),
            ident_in_group: udint_to_identingroup(i as u32 + 1),
        }))?;
    }
    e.command(AxisCommand::Ca(CaCommand::GroupEnable {
        group: group.into(),
    }))?;
    e.step(Tick { index: 1, dt }, &mut ev);
    Ok(e)
}

/// `n` movers, 300 mm apart on a ring of `n · 300` mm, one CA group "ring" (Standard,
/// default gap 100), each moving forward endlessly (MoveRelativeCA +1e9 mm at 1000 mm/s);
/// stepped 1 s at 1 ms so that the train is in motion. For timing `step` (benches).
pub fn bench_ring(n_axes: usize) -> AxisEngine {
    let n = n_axes.max(1);
    let movers: Vec<(String, f64)> = (0..n)
        .map(|i| (format!("m{i}"), (n - 1 - i) as f64 * 300.0))
        .collect();
    let cfg = CaGroupConfig {
        rail_length: n as f64 * 300.0,
        ..CaGroupConfig::default()
    };
    let dt = 0.001;
    let mut e = match ca_engine(&movers, "ring", cfg, dt) {
        Ok(e) => e,
        Err(r) => panic!("bench_ring setup: {r}"),
    };
    for (name, _) in &movers {
        let r = e.command(AxisCommand::Ca(CaCommand::MoveRelative(MoveRelativeCa {
            axis: name.clone(),
            distance: McLreal::Value(1e9),
            velocity: McLreal::Value(1000.0),
            ..MoveRelativeCa::default()
        })));
        if let Err(r) = r {
            panic!("bench_ring move: {r}");
        }
    }
    let mut ev = Vec::new();
    for k in 0..1000 {
        ev.clear();
        e.step(Tick { index: 2 + k, dt }, &mut ev);
    }
    e
}

/// A dense ring: `n` movers 150 mm apart (a Standard follower at 1000 mm/s needs about
/// 200 mm), all moving forward endlessly, so every follower is CA-limited and the planner's
/// root searches run; stepped 1 s. For timing `step` (benches).
pub fn bench_dense_train(n_axes: usize) -> AxisEngine {
    let n = n_axes.max(1);
    let movers: Vec<(String, f64)> = (0..n)
        .map(|i| (format!("m{i}"), (n - 1 - i) as f64 * 150.0))
        .collect();
    let cfg = CaGroupConfig {
        rail_length: n as f64 * 150.0 + 1000.0,
        ..CaGroupConfig::default()
    };
    let dt = 0.001;
    let mut e = match ca_engine(&movers, "g", cfg, dt) {
        Ok(e) => e,
        Err(r) => panic!("bench_dense_train setup: {r}"),
    };
    for (name, _) in &movers {
        let r = e.command(AxisCommand::Ca(CaCommand::MoveRelative(MoveRelativeCa {
            axis: name.clone(),
            distance: McLreal::Value(1e9),
            velocity: McLreal::Value(1000.0),
            ..MoveRelativeCa::default()
        })));
        if let Err(r) = r {
            panic!("bench_dense_train move: {r}");
        }
    }
    let mut ev = Vec::new();
    for k in 0..1000 {
        ev.clear();
        e.step(Tick { index: 2 + k, dt }, &mut ev);
    }
    e
}
