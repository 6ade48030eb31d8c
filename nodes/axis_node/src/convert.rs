//! Snapshots to messages: `~/axis_states`, `~/axes/<axis>/state`, `joint_states`.

use axis_engine::{AxisEngine, AxisSnapshot, AxisStatus};
use motion_msgs::deps::builtin_interfaces::msg::Time;
use motion_msgs::deps::sensor_msgs::msg::JointState;
use motion_msgs::deps::std_msgs::msg::Header;
use motion_msgs::msg::{AxisState, AxisStateArray};
use motion_runtime::cycle::Stamped;
use motion_runtime::shell::stamp;
use motion_runtime::{NodeShell, ShellError};

/// One axis as `motion_msgs/AxisState`.
pub fn axis_state(a: &AxisStatus, stamp: Time) -> AxisState {
    AxisState {
        stamp,
        name: a.name.clone(),
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
    }
}

/// All axes as `motion_msgs/AxisStateArray`.
pub fn axis_state_array(s: &Stamped<AxisSnapshot>) -> AxisStateArray {
    AxisStateArray {
        stamp: stamp(s),
        axes: s
            .state
            .axes
            .iter()
            .map(|a| axis_state(a, stamp(s)))
            .collect(),
    }
}

/// All axes as `sensor_msgs/JointState` (actual position and velocity; effort = set torque
/// is not modelled yet and left empty).
pub fn joint_state(s: &Stamped<AxisSnapshot>) -> JointState {
    JointState {
        header: Header {
            stamp: stamp(s),
            frame_id: String::new(),
        },
        name: s.state.axes.iter().map(|a| a.name.clone()).collect(),
        position: s.state.axes.iter().map(|a| a.act_pos).collect(),
        velocity: s.state.axes.iter().map(|a| a.act_velo).collect(),
        effort: Vec::new(),
    }
}

pub(crate) fn register_topics(
    shell: &mut NodeShell<AxisEngine>,
    names: Vec<String>,
) -> Result<(), ShellError> {
    shell.state_publisher(
        "~/axis_states",
        AxisStateArray::type_name(),
        axis_state_array,
    )?;
    shell.state_publisher("joint_states", JointState::type_name(), joint_state)?;
    for (i, name) in names.into_iter().enumerate() {
        shell.state_publisher(
            &format!("~/axes/{name}/state"),
            AxisState::type_name(),
            move |s| match s.state.axes.get(i) {
                Some(a) => axis_state(a, stamp(s)),
                None => AxisState::default(),
            },
        )?;
    }
    Ok(())
}
