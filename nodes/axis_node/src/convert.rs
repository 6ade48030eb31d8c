//! Snapshots to messages: `~/axis_states`, `~/axes/<axis>/state`, `joint_states`.

use axis_engine::{AxisEngine, AxisSnapshot, AxisStatus};
use motion_msgs::deps::builtin_interfaces::msg::Time;
use motion_msgs::deps::sensor_msgs::msg::JointState;
use motion_msgs::msg::{AxisState, AxisStateArray};
use motion_runtime::cycle::Stamped;
use motion_runtime::shell::{header, stamp};
use motion_runtime::{NodeShell, ShellError};

/// One axis as `motion_msgs/AxisState`.
pub fn axis_state(a: &AxisStatus, stamp: Time) -> AxisState {
    let mut m = AxisState::default();
    axis_state_into(a, stamp, &mut m);
    m
}

/// [`axis_state`] into `m`, keeping its name's memory (a message refilled every cycle).
pub fn axis_state_into(a: &AxisStatus, stamp: Time, m: &mut AxisState) {
    let mut name = std::mem::take(&mut m.name);
    if name != *a.name {
        name.clear();
        name.push_str(&a.name);
    }
    *m = AxisState {
        header: header(stamp),
        name,
        motion_state: a.motion_state as u8,
        state_dword: a.state_dword,
        error_code: a.error_code,
        axis_state: a.axis_state,
        couple_state: a.couple_state,
        set_pos: a.set_pos,
        set_velo: a.set_velo,
        set_acc: a.set_acc,
        set_jerk: a.set_jerk,
        act_pos: a.act_pos,
        act_velo: a.act_velo,
        act_acc: a.act_acc,
        pos_diff: a.pos_diff,
        target_pos: a.target_pos,
        modulo_act_pos: a.modulo_act_pos,
        modulo_act_turns: a.modulo_act_turns,
        r#override: a.override_percent,
        power_status: a.power_status,
        homed: a.homed,
        has_job: a.has_job,
        cmd_buffered: a.cmd_buffered,
        cmd_no: a.cmd_no,
        abs_phasing_pos: a.ext.abs_phasing_pos,
        act_pos_without_pos_correction: a.ext.act_pos_without_pos_correction,
        position_correction: a.ext.position_correction,
        drive_set_pos: a.ext.drive_set_pos,
        ext_set_pos: a.ext.ext_set_pos,
        ext_set_velo: a.ext.ext_set_velo,
        ext_set_acc: a.ext.ext_set_acc,
        ext_torque: a.ext.ext_torque,
        encoder_increments: a.ext.encoder_increments,
        control_loop_index: a.ext.control_loop_index,
        homing_state: a.homing_state,
        modulo_set_pos: a.modulo_set_pos,
        modulo_set_turns: a.modulo_set_turns,
        set_position_offset: a.set_position_offset,
        set_torque: a.set_torque,
        raw_set_pos: a.raw_pos,
        raw_act_pos: a.raw_act_pos,
        home_cam: a.home_cam,
    };
}

/// All axes as `motion_msgs/AxisStateArray`, into `m` (its entries refilled in place).
pub fn axis_state_array_into(s: &Stamped<AxisSnapshot>, m: &mut AxisStateArray) {
    let AxisStateArray { header: at, axes } = m;
    *at = header(stamp(s));
    axes.resize_with(s.state.axes.len(), AxisState::default);
    for (a, m) in s.state.axes.iter().zip(axes) {
        axis_state_into(a, stamp(s), m);
    }
}

/// The axis node's frame on `/tf_static` (the base its axes are mounted on; a URDF's joints
/// hang below it through `joint_states`).
pub const FRAME: &str = "axes_base";

/// How an axis appears in `joint_states` (REP-103 SI units): a prismatic axis counts in mm
/// (published in m), a revolute one in degrees (published in rad). The PLCopen topics keep the
/// axis's own units.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum JointType {
    /// Linear axis, positions in mm.
    #[default]
    Prismatic,
    /// Rotary axis, positions in degrees.
    Revolute,
}

impl JointType {
    /// From the launch config's `joint_type` value.
    pub fn from_yaml(v: &serde_yaml::Value) -> Option<Self> {
        match v.as_str()? {
            "prismatic" => Some(JointType::Prismatic),
            "revolute" => Some(JointType::Revolute),
            _ => None,
        }
    }

    /// Factor from the axis's units to SI (m or rad).
    pub fn to_si(self) -> f64 {
        match self {
            JointType::Prismatic => 1e-3,
            JointType::Revolute => std::f64::consts::PI / 180.0,
        }
    }
}

/// All axes as `sensor_msgs/JointState` in SI units (actual position and velocity; effort =
/// set torque is not modelled yet and left empty).
/// Written into `js`: its names are rebuilt only when the axes' names differ (never while a
/// node runs), its arrays keep their memory.
pub fn joint_state_into(s: &Stamped<AxisSnapshot>, joints: &[JointType], js: &mut JointState) {
    let k = |i: usize| joints.get(i).copied().unwrap_or_default().to_si();
    let axes = &s.state.axes;
    let JointState {
        header,
        name,
        position,
        velocity,
        effort,
    } = js;
    *header = motion_runtime::shell::header(stamp(s));
    if !name
        .iter()
        .map(String::as_str)
        .eq(axes.iter().map(|a| &*a.name))
    {
        *name = axes.iter().map(|a| str::to_owned(&a.name)).collect();
    }
    position.clear();
    position.extend(axes.iter().enumerate().map(|(i, a)| a.act_pos * k(i)));
    velocity.clear();
    velocity.extend(axes.iter().enumerate().map(|(i, a)| a.act_velo * k(i)));
    effort.clear();
}

pub(crate) fn register_topics(
    shell: &mut NodeShell<AxisEngine>,
    names: Vec<String>,
    joints: Vec<JointType>,
) -> Result<(), ShellError> {
    // Refilled messages: a lockstep stream of every cycle allocates no names or arrays.
    shell.state_publisher_refill(
        "~/axis_states",
        AxisStateArray::type_name(),
        axis_state_array_into,
    )?;
    shell.state_publisher_refill("joint_states", JointState::type_name(), move |s, js| {
        joint_state_into(s, &joints, js)
    })?;
    for (i, name) in names.into_iter().enumerate() {
        shell.state_publisher_refill(
            &format!("~/axes/{name}/state"),
            AxisState::type_name(),
            move |s, m| match s.state.axes.get(i) {
                Some(a) => axis_state_into(a, stamp(s), m),
                None => *m = AxisState::default(),
            },
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use motion_core::Engine;
    use motion_msgs::deps::std_msgs::msg::Header;

    /// REP-103: prismatic mm -> m, revolute deg -> rad.
    #[test]
    fn joint_states_are_in_si_units() {
        let e = AxisEngine::new(vec![
            ("x".into(), Default::default()),
            ("t".into(), Default::default()),
        ])
        .unwrap();
        let mut snap = Stamped {
            cycle: 0,
            sim_time: 0.0,
            ros_time_ns: 0,
            state: e.snapshot(),
        };
        snap.state.axes[0].act_pos = 250.0;
        snap.state.axes[0].act_velo = -100.0;
        snap.state.axes[1].act_pos = 90.0;
        snap.state.axes[1].act_velo = 180.0;
        let joints = [JointType::Prismatic, JointType::Revolute];
        // A fresh message, and one refilled from another node's (other names, longer arrays,
        // an effort and a frame): the same message.
        let mut fresh = JointState::default();
        joint_state_into(&snap, &joints, &mut fresh);
        let mut old = JointState {
            header: Header {
                stamp: Time { sec: 7, nanosec: 7 },
                frame_id: "old".into(),
            },
            name: vec!["a".into(), "b".into(), "c".into()],
            position: vec![1.0; 3],
            velocity: vec![2.0; 3],
            effort: vec![3.0; 3],
        };
        joint_state_into(&snap, &joints, &mut old);
        for js in [&fresh, &old] {
            assert_eq!(js.name, ["x", "t"]);
            assert!(js.header.frame_id.is_empty() && js.effort.is_empty());
            assert_eq!(js.header.stamp, stamp(&snap));
            assert_eq!((js.position.len(), js.velocity.len()), (2, 2));
            assert!((js.position[0] - 0.25).abs() < 1e-12 && (js.velocity[0] + 0.1).abs() < 1e-12);
            let pi = std::f64::consts::PI;
            assert!(
                (js.position[1] - pi / 2.0).abs() < 1e-12 && (js.velocity[1] - pi).abs() < 1e-12
            );
        }
    }

    /// A refilled `~/axis_states` (and so each `~/axes/<axis>/state`) equals a fresh one,
    /// also when refilled from a message of more, other axes.
    #[test]
    fn refilled_axis_states_equal_fresh_ones() {
        let e = |names: &[&str]| {
            AxisEngine::new(
                names
                    .iter()
                    .map(|n| (n.to_string(), Default::default()))
                    .collect(),
            )
            .unwrap()
        };
        let mut snap = Stamped {
            cycle: 3,
            sim_time: 0.003,
            ros_time_ns: 3_000_000,
            state: e(&["x", "y"]).snapshot(),
        };
        snap.state.axes[1].act_pos = 12.5;
        snap.state.axes[1].ext.encoder_increments = 99;
        let mut fresh = AxisStateArray::default();
        axis_state_array_into(&snap, &mut fresh);
        let other = Stamped {
            cycle: 9,
            sim_time: 0.009,
            ros_time_ns: 9_000_000,
            state: e(&["longer_name", "b", "c"]).snapshot(),
        };
        let mut refilled = AxisStateArray::default();
        axis_state_array_into(&other, &mut refilled);
        refilled.axes[1].home_cam = true;
        axis_state_array_into(&snap, &mut refilled);
        assert_eq!(refilled, fresh);
        assert_eq!(fresh.axes.len(), 2);
        assert_eq!(
            (fresh.axes[1].name.as_str(), fresh.axes[1].act_pos),
            ("y", 12.5)
        );
        assert_eq!(fresh.axes[1], axis_state(&snap.state.axes[1], stamp(&snap)));
    }
}
