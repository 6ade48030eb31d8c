//! Snapshots and cell events to messages (pick_and_place.md §18): `~/state`, `~/workpieces`,
//! `~/events` and the RViz view `~/markers` (frame [`FRAME`], metres).

use crate::cell::{Cell, CellSnapshot, EventBatch};
use motion_msgs::deps::builtin_interfaces::msg::{Duration, Time};
use motion_msgs::deps::geometry_msgs::msg::{Point, Pose, Quaternion, Vector3};
use motion_msgs::deps::std_msgs::msg::{ColorRGBA, Header};
use motion_msgs::deps::visualization_msgs::msg::{Marker, MarkerArray};
use motion_msgs::msg::{
    BeltWorkpiece, BeltWorkpieces, PickPlaceBelt, PickPlaceEvent, PickPlaceState,
};
use motion_runtime::cycle::Stamped;
use motion_runtime::shell::{header, resolve_name, stamp, stamp_ns};
use motion_runtime::{NodeShell, ShellError};
use pickplace_engine::belt::WorkpieceEventKind;
use pickplace_engine::snapshot::{BeltSnapshot, ProfilePhase, WorkpieceSnapshot};
use pickplace_engine::{CellEvent, GripperEvent, PickPlaceSnapshot};
use tokio::sync::mpsc::UnboundedReceiver;

/// Frame of the markers: the cell's machine coordinate system (MCS), in metres.
pub const FRAME: &str = "pickplace_mcs";
const MM: f64 = 0.001;
/// Drawn width and thickness of a belt [mm] (the manual gives belts no width).
const BELT_WIDTH: f64 = 150.0;
const BELT_THICKNESS: f64 = 10.0;
/// Drawn edge of a workpiece cube [mm].
const WORKPIECE_SIZE: f64 = 30.0;
/// Drawn diameter of the TCP sphere [mm].
const TCP_SIZE: f64 = 25.0;

fn shown(b: &BeltSnapshot) -> bool {
    b.configured || b.velocity != 0.0 || !b.workpieces.is_empty()
}

fn workpiece(belt: u8, w: &WorkpieceSnapshot) -> BeltWorkpiece {
    BeltWorkpiece {
        belt,
        id: w.id,
        visible: w.visible,
        reserved: w.reserved,
        belt_position: w.belt_position,
        mcs_position: w.mcs_position,
    }
}

fn phase(p: ProfilePhase) -> u8 {
    match p {
        ProfilePhase::ToTarget => PickPlaceState::PHASE_TO_TARGET,
        ProfilePhase::ToPark => PickPlaceState::PHASE_TO_PARK,
        ProfilePhase::WaitingAtPark => PickPlaceState::PHASE_WAITING_AT_PARK,
        ProfilePhase::SyncDwell => PickPlaceState::PHASE_SYNC_DWELL,
        ProfilePhase::AtTarget => PickPlaceState::PHASE_AT_TARGET,
    }
}

/// `~/state`: every output of §3.3, the TCP, the active profile and the belts.
pub fn state(s: &Stamped<CellSnapshot>) -> PickPlaceState {
    let c: &PickPlaceSnapshot = &s.state.cell;
    let o = &c.outputs;
    let p = c.active_profile;
    PickPlaceState {
        header: header(stamp(s)),
        cycle: s.cycle,
        state: c.state as u8,
        tcp_x: c.tcp[0],
        tcp_y: c.tcp[1],
        tcp_z: c.tcp[2],
        tcp_a: c.tcp[3],
        tcp_b: c.tcp[4],
        tcp_c: c.tcp[5],
        tcp_aux1: c.tcp[6],
        tcp_velocity: c.tcp_velocity,
        gripper_closed: c.gripper_closed,
        has_held_workpiece: c.held_workpiece.is_some(),
        held_workpiece: c.held_workpiece.unwrap_or(0),
        internal_control_active: o.internal_control_active,
        group_enabled: o.status_agbc.group_enabled,
        group_error: o.status_agbc.group_error,
        group_error_id: o.status_agbc.group_error_id,
        group_homed: o.status_agbc.group_homed,
        error: o.error,
        warning: o.warning,
        error_id: o.error_id,
        axis_error: o.error_info.map(|e| e.error),
        axis_error_id: o.error_info.map(|e| e.error_id),
        axes_enabled: o.axes_enabled,
        axes_group_enabled: o.axes_group_enabled,
        signal_flow_set_target: o.signal_flow.set_target,
        signal_flow_select_axis: o.signal_flow.select_axis,
        signal_flow_tracking_mode: o.signal_flow.tracking_mode,
        signal_flow_override: o.signal_flow.override_applied,
        signal_flow_stop_inputs: o.signal_flow.stop_inputs,
        done: o.done,
        busy: o.busy,
        axes_group_homed: o.axes_group_homed,
        in_position: o.in_position,
        hw_limit_switch_active: o.hw_limit_switch_active,
        sw_limit_switch_active: o.sw_limit_switch_active,
        hw_limit_switch_neg: o.hw_limit_switch_neg,
        hw_limit_switch_pos: o.hw_limit_switch_pos,
        sw_limit_enabled: o.sw_limit_enabled,
        sw_limit_switch_active_axes: o.sw_limit_switch_active_axes,
        path_hold: o.path_hold,
        gripper_ctrl_active: o.gripper_ctrl_active,
        pulse_gripper: o.pulse_gripper,
        set_path_vel_out: o.set_path_vel_out,
        path_preparation_time: o.path_preparation_time,
        pre_calc_profile_time: o.pre_calc_profile_time,
        act_pos: o.act_pos,
        act_vel: o.act_vel,
        profile_point_passed: o.profile_point_passed,
        profile_in_preparation: o.profile_in_preparation,
        acc_dec_sync: o.acc_dec_sync,
        synchronised: o.synchronised,
        in_target: o.in_target,
        in_park_pos: o.in_park_pos,
        set_target_out: o.set_target_out,
        profile_active: p.is_some(),
        profile_set_target: p.map(|p| p.set_target).unwrap_or(0),
        profile_phase: p.map(|p| phase(p.phase)).unwrap_or(0),
        profile_sigma: p.map(|p| p.sigma).unwrap_or(0.0),
        profile_length: p.map(|p| p.length).unwrap_or(0.0),
        profile_coupling: p.map(|p| p.coupling).unwrap_or(0.0),
        profile_has_workpiece: p.and_then(|p| p.workpiece).is_some(),
        profile_workpiece: p.and_then(|p| p.workpiece).unwrap_or(0),
        queued_profiles: c.queued_profiles as u32,
        belts: c
            .belts
            .iter()
            .filter(|b| shown(b))
            .map(|b| PickPlaceBelt {
                belt: b.belt,
                configured: b.configured,
                position: b.position,
                velocity: b.velocity,
                workpieces: b.workpieces.iter().map(|w| workpiece(b.belt, w)).collect(),
            })
            .collect(),
    }
}

/// `~/workpieces`: every tracked workpiece of every belt.
pub fn workpieces(s: &Stamped<CellSnapshot>) -> BeltWorkpieces {
    BeltWorkpieces {
        header: header(stamp(s)),
        workpieces: s
            .state
            .cell
            .belts
            .iter()
            .flat_map(|b| b.workpieces.iter().map(|w| workpiece(b.belt, w)))
            .collect(),
    }
}

/// One cell event as `motion_msgs/PickPlaceEvent` (header stamp = ROS time of its cycle).
pub fn event(e: &CellEvent, stamp: Time) -> PickPlaceEvent {
    let base = PickPlaceEvent {
        header: header(stamp),
        ..Default::default()
    };
    match *e {
        CellEvent::StateChanged { cycle, from, to } => PickPlaceEvent {
            cycle,
            kind: PickPlaceEvent::KIND_STATE_CHANGED,
            from_state: from as u8,
            to_state: to as u8,
            ..base
        },
        CellEvent::GripperPulse { cycle, kind } => PickPlaceEvent {
            cycle,
            kind: PickPlaceEvent::KIND_GRIPPER_PULSE,
            gripper: match kind {
                GripperEvent::Close => PickPlaceEvent::GRIPPER_CLOSE,
                GripperEvent::Open => PickPlaceEvent::GRIPPER_OPEN,
            },
            ..base
        },
        CellEvent::Workpiece {
            cycle,
            belt,
            id,
            kind,
        } => PickPlaceEvent {
            cycle,
            kind: PickPlaceEvent::KIND_WORKPIECE,
            belt,
            workpiece_id: id,
            workpiece_event: match kind {
                WorkpieceEventKind::Received => PickPlaceEvent::WORKPIECE_RECEIVED,
                WorkpieceEventKind::Visible => PickPlaceEvent::WORKPIECE_VISIBLE,
                WorkpieceEventKind::Picked => PickPlaceEvent::WORKPIECE_PICKED,
                WorkpieceEventKind::Placed => PickPlaceEvent::WORKPIECE_PLACED,
                WorkpieceEventKind::Missed => PickPlaceEvent::WORKPIECE_MISSED,
                WorkpieceEventKind::Rejected => PickPlaceEvent::WORKPIECE_REJECTED,
            },
            ..base
        },
        CellEvent::Diagnostic { cycle, id, error } => PickPlaceEvent {
            cycle,
            kind: PickPlaceEvent::KIND_DIAGNOSTIC,
            diagnostic_id: id,
            error,
            ..base
        },
    }
}

fn color(r: f32, g: f32, b: f32, a: f32) -> ColorRGBA {
    ColorRGBA { r, g, b, a }
}

fn point(p: [f64; 3]) -> Point {
    Point {
        x: p[0] * MM,
        y: p[1] * MM,
        z: p[2] * MM,
    }
}

/// Quaternion of R = Rz(C)·Ry(B)·Rx(A), angles in degrees (the belt frame of §7.1).
pub fn quaternion_zyx(a_deg: f64, b_deg: f64, c_deg: f64) -> Quaternion {
    motion_runtime::shell::quaternion_rpy(
        a_deg.to_radians(),
        b_deg.to_radians(),
        c_deg.to_radians(),
    )
}

/// Rotates `v` by R = Rz(C)·Ry(B)·Rx(A) (degrees).
fn rotate_zyx(a_deg: f64, b_deg: f64, c_deg: f64, v: [f64; 3]) -> [f64; 3] {
    let (sa, ca) = a_deg.to_radians().sin_cos();
    let (sb, cb) = b_deg.to_radians().sin_cos();
    let (sc, cc) = c_deg.to_radians().sin_cos();
    let x = [v[0], ca * v[1] - sa * v[2], sa * v[1] + ca * v[2]];
    let y = [cb * x[0] + sb * x[2], x[1], -sb * x[0] + cb * x[2]];
    [cc * y[0] - sc * y[1], sc * y[0] + cc * y[1], y[2]]
}

/// The cell for RViz: each belt's working area as a flat box under its belt frame (ns `belts`,
/// id = belt number; deleted while a belt is not configured), the visible workpieces as cubes
/// (ns `workpieces`; orange = reserved as a target), the TCP as a sphere (ns `tcp`; green while
/// the gripper holds a workpiece) and the TCP path of the running leg as a line strip (ns
/// `path`; deleted when no path runs).
pub fn markers(s: &Stamped<CellSnapshot>) -> MarkerArray {
    let header = Header {
        stamp: stamp(s),
        frame_id: FRAME.into(),
    };
    let c = &s.state.cell;
    let mut out = Vec::with_capacity(19);
    for (i, b) in c.belts.iter().enumerate().take(16) {
        let par = s.state.belt_params.get(i).copied();
        let mut m = Marker {
            header: header.clone(),
            ns: "belts".into(),
            id: i32::from(b.belt),
            r#type: Marker::CUBE,
            ..Default::default()
        };
        match par.filter(|_| b.configured) {
            Some(p) => {
                let o = p.conveyor_belt_origin;
                let length = p.upper_sync_limit - p.lower_sync_limit;
                let centre_b = [
                    (p.lower_sync_limit + p.upper_sync_limit) / 2.0,
                    0.0,
                    -BELT_THICKNESS / 2.0,
                ];
                let r = rotate_zyx(o[3], o[4], o[5], centre_b);
                m.action = Marker::ADD;
                m.pose = Pose {
                    position: point([o[0] + r[0], o[1] + r[1], o[2] + r[2]]),
                    orientation: quaternion_zyx(o[3], o[4], o[5]),
                };
                m.scale = Vector3 {
                    x: length * MM,
                    y: BELT_WIDTH * MM,
                    z: BELT_THICKNESS * MM,
                };
                m.color = if b.velocity != 0.0 {
                    color(0.2, 0.35, 0.6, 1.0)
                } else {
                    color(0.3, 0.3, 0.35, 1.0)
                };
            }
            None => m.action = Marker::DELETE,
        }
        out.push(m);
    }
    let visible: Vec<&WorkpieceSnapshot> = c
        .belts
        .iter()
        .flat_map(|b| b.workpieces.iter())
        .filter(|w| w.visible)
        .collect();
    out.push(Marker {
        header: header.clone(),
        ns: "workpieces".into(),
        id: 0,
        r#type: Marker::CUBE_LIST,
        action: if visible.is_empty() {
            Marker::DELETE
        } else {
            Marker::ADD
        },
        scale: Vector3 {
            x: WORKPIECE_SIZE * MM,
            y: WORKPIECE_SIZE * MM,
            z: WORKPIECE_SIZE * MM,
        },
        color: color(0.9, 0.9, 0.2, 1.0),
        points: visible
            .iter()
            .map(|w| {
                point([
                    w.mcs_position[0],
                    w.mcs_position[1],
                    w.mcs_position[2] + WORKPIECE_SIZE / 2.0,
                ])
            })
            .collect(),
        colors: visible
            .iter()
            .map(|w| {
                if w.reserved {
                    color(1.0, 0.55, 0.1, 1.0)
                } else {
                    color(0.9, 0.9, 0.2, 1.0)
                }
            })
            .collect(),
        ..Default::default()
    });
    out.push(Marker {
        header: header.clone(),
        ns: "tcp".into(),
        id: 0,
        r#type: Marker::SPHERE,
        action: Marker::ADD,
        pose: Pose {
            position: point([c.tcp[0], c.tcp[1], c.tcp[2]]),
            orientation: Quaternion::default(),
        },
        scale: Vector3 {
            x: TCP_SIZE * MM,
            y: TCP_SIZE * MM,
            z: TCP_SIZE * MM,
        },
        color: if c.held_workpiece.is_some() || c.gripper_closed {
            color(0.1, 0.8, 0.2, 1.0)
        } else {
            color(0.9, 0.2, 0.2, 1.0)
        },
        ..Default::default()
    });
    out.push(Marker {
        header,
        ns: "path".into(),
        id: 0,
        r#type: Marker::LINE_STRIP,
        action: if s.state.path.len() < 2 {
            Marker::DELETE
        } else {
            Marker::ADD
        },
        scale: Vector3 {
            x: 0.003,
            y: 0.0,
            z: 0.0,
        },
        color: color(0.2, 0.9, 0.9, 1.0),
        points: s.state.path.iter().map(|p| point(*p)).collect(),
        lifetime: Duration::default(),
        ..Default::default()
    });
    MarkerArray { markers: out }
}

/// Registers `~/state`, `~/workpieces`, `~/markers` (at the state rate) and `~/events` (as the
/// cycle reports them).
pub(crate) fn register_topics(
    shell: &mut NodeShell<Cell>,
    events: UnboundedReceiver<EventBatch>,
) -> Result<(), ShellError> {
    shell.state_publisher("~/state", PickPlaceState::type_name(), state)?;
    shell.state_publisher("~/workpieces", BeltWorkpieces::type_name(), workpieces)?;
    shell.state_publisher("~/markers", MarkerArray::type_name(), markers)?;
    register_events(shell, events)
}

fn register_events(
    shell: &mut NodeShell<Cell>,
    mut events: UnboundedReceiver<EventBatch>,
) -> Result<(), ShellError> {
    use ros2_client::qos::{Durability, History};
    // Reliable with a deep history: events are single-cycle facts a client must not miss.
    let qos = ros2_client::QosProfile::publisher_default()
        .durability(Durability::Volatile)
        .history(History::KeepLast { depth: 1000 });
    let name = resolve_name(&shell.settings, "~/events")?;
    let topic = shell
        .node
        .create_topic(&name, PickPlaceEvent::type_name(), &qos)
        .map_err(|e| ShellError(format!("topic ~/events: {e:?}")))?;
    let publisher = shell
        .node
        .create_publisher::<PickPlaceEvent>(&topic, None)
        .map_err(|e| ShellError(format!("publisher ~/events: {e:?}")))?;
    let publisher = motion_runtime::record::RecordedPublisher::new(publisher, name);
    let handle = shell.handle.clone();
    shell.spawn(async move {
        while let Some((t, batch)) = events.recv().await {
            let ns = handle.snapshot().ros_time_at(t);
            let at = stamp_ns(ns);
            for e in &batch {
                if let Err(err) = publisher.publish(event(e, at.clone()), ns).await {
                    tracing::warn!("events publish failed: {err:?}");
                }
            }
        }
    });
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn belt_rotation_matches_the_quaternion() {
        // W8's belt: C = 180 maps belt (x, y, z) to (−x, −y, z).
        let r = rotate_zyx(0.0, 0.0, 180.0, [1.0, 2.0, 3.0]);
        assert!(
            (r[0] + 1.0).abs() < 1e-12 && (r[1] + 2.0).abs() < 1e-12 && (r[2] - 3.0).abs() < 1e-12
        );
        let q = quaternion_zyx(0.0, 0.0, 180.0);
        assert!(q.z.abs() > 0.999999 && q.w.abs() < 1e-9);
        // A general rotation: q·v·q* equals R·v.
        let (a, b, c) = (30.0, -20.0, 75.0);
        let q = quaternion_zyx(a, b, c);
        let v = [0.3, -1.2, 2.0];
        let qv = rotate_by_quaternion(&q, v);
        let rv = rotate_zyx(a, b, c, v);
        for i in 0..3 {
            assert!((qv[i] - rv[i]).abs() < 1e-12, "{qv:?} {rv:?}");
        }
    }

    #[test]
    fn events_keep_cycle_kind_and_payload() {
        use pickplace_engine::TmState;
        let e = event(
            &CellEvent::StateChanged {
                cycle: 7,
                from: TmState::Ready,
                to: TmState::MovePp,
            },
            stamp_ns(8_000_000),
        );
        assert_eq!(
            (e.cycle, e.kind, e.from_state, e.to_state),
            (7, PickPlaceEvent::KIND_STATE_CHANGED, 1, 9)
        );
        assert_eq!((e.header.stamp.sec, e.header.stamp.nanosec), (0, 8_000_000));
        let e = event(
            &CellEvent::GripperPulse {
                cycle: 3,
                kind: GripperEvent::Open,
            },
            stamp_ns(0),
        );
        assert_eq!(
            (e.kind, e.gripper),
            (
                PickPlaceEvent::KIND_GRIPPER_PULSE,
                PickPlaceEvent::GRIPPER_OPEN
            )
        );
        let e = event(
            &CellEvent::Workpiece {
                cycle: 3,
                belt: 2,
                id: 11,
                kind: WorkpieceEventKind::Missed,
            },
            stamp_ns(0),
        );
        assert_eq!(
            (e.kind, e.belt, e.workpiece_id, e.workpiece_event),
            (
                PickPlaceEvent::KIND_WORKPIECE,
                2,
                11,
                PickPlaceEvent::WORKPIECE_MISSED
            )
        );
        let e = event(
            &CellEvent::Diagnostic {
                cycle: 3,
                id: 17918,
                error: false,
            },
            stamp_ns(0),
        );
        assert_eq!(
            (e.kind, e.diagnostic_id, e.error),
            (PickPlaceEvent::KIND_DIAGNOSTIC, 17918, false)
        );
    }

    fn rotate_by_quaternion(q: &Quaternion, v: [f64; 3]) -> [f64; 3] {
        let (w, x, y, z) = (q.w, q.x, q.y, q.z);
        let u = [x, y, z];
        let cross = |a: [f64; 3], b: [f64; 3]| {
            [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ]
        };
        let t = cross(u, v).map(|e| 2.0 * e);
        let ut = cross(u, t);
        [
            v[0] + w * t[0] + ut[0],
            v[1] + w * t[1] + ut[1],
            v[2] + w * t[2] + ut[2],
        ]
    }
}
