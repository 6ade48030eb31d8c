//! Snapshots to messages (xplanar.md §4.4, §9): `~/state` (motion_msgs/PlanarState, the
//! manual's units mm and deg), `~/mover_poses` (geometry_msgs/PoseArray) and `~/markers`
//! (visualization_msgs/MarkerArray) for RViz.
//!
//! RViz side: frame [`FRAME_ID`], metres (mm / 1000), the plane's x/y axes = the coordinate
//! system's x/y, z up (the mover's lift z). A mover's orientation is roll = a (tilt about x),
//! pitch = b (tilt about y), yaw = c (rotation about the vertical), in degrees in the state,
//! as a quaternion in the poses. Several coordinate systems (parts moved between levels) are
//! drawn in the same frame.

use motion_msgs::deps::builtin_interfaces::msg::Time;
use motion_msgs::deps::geometry_msgs::msg::{Point, Pose, PoseArray, Quaternion, Vector3};
use motion_msgs::deps::std_msgs::msg::{ColorRGBA, Header};
use motion_msgs::deps::visualization_msgs::msg::{Marker, MarkerArray};
use motion_msgs::msg::{
    PlanarEnvironmentState, PlanarGroupState, PlanarMoverState, PlanarPartState, PlanarState,
};
use motion_runtime::cycle::Stamped;
use motion_runtime::shell::{header, stamp};
use motion_runtime::{NodeShell, ShellError};
use planar_engine::{MoverSnapshot, PlanarConfig, PlanarEngine, PlanarSnapshot};
use std::sync::Arc;

/// The TF frame of the mover poses and markers: the plane of the coordinate systems.
pub const FRAME_ID: &str = "planar_env";

/// Stator side \[mm\] (xplanar.md §0).
const STATOR_SIDE: f64 = 240.0;
/// Drawn mover thickness \[mm\] (the manual gives none; about an APM4330's).
const MOVER_THICKNESS: f64 = 12.0;
const MM: f64 = 1e-3;

/// What the markers need from the configuration: mover footprints and part tiles.
#[derive(Clone, Debug, Default)]
pub struct Geometry {
    /// (width, height) \[mm\] per mover, configuration order.
    pub mover_sizes: Vec<(f64, f64)>,
    /// Part-local lower-left tile corners \[mm\] per part, configuration order.
    pub part_tiles: Vec<Vec<[f64; 2]>>,
    /// Sampled track paths (kept up to date by the node, xplanar.md §5.4).
    pub track_paths: crate::tracks::TrackPaths,
}

impl Geometry {
    /// From the engine configuration.
    pub fn from_config(cfg: &PlanarConfig) -> Self {
        Geometry {
            mover_sizes: cfg.movers.iter().map(|m| (m.width, m.height)).collect(),
            part_tiles: cfg.parts.iter().map(|p| p.tiles.clone()).collect(),
            track_paths: Default::default(),
        }
    }

    /// Lower-left corners \[mm\] of every stator now: the parts' tiles at their current
    /// positions, or the stators added by `AddStator` when no parts are configured.
    pub fn stators(&self, s: &PlanarSnapshot) -> Vec<[f64; 2]> {
        if s.parts.is_empty() {
            return s.environment.added_stators.clone();
        }
        s.parts
            .iter()
            .zip(&self.part_tiles)
            .flat_map(|(p, tiles)| {
                tiles
                    .iter()
                    .map(move |t| [p.position.x + t[0], p.position.y + t[1]])
            })
            .collect()
    }
}

/// One mover as `motion_msgs/PlanarMoverState`.
pub fn mover_state(m: &MoverSnapshot) -> PlanarMoverState {
    let mut out = PlanarMoverState {
        name: m.name.clone(),
        oid: m.oid,
        state: m.state as u8,
        command_mode: m.command_mode as u8,
        busy_mover: m.busy.busy_mover,
        busy_xyc: m.busy.busy_xyc,
        busy_c: m.busy.busy_c,
        busy_z: m.busy.busy_z,
        busy_a: m.busy.busy_a,
        busy_b: m.busy.busy_b,
        group: m.group.clone().unwrap_or_default(),
        group_oid: m.group_oid,
        part: m.part.clone().unwrap_or_default(),
        part_oid: m.part_oid,
        coordinate_system_oid: m.coordinate_system_oid,
        error_id: m.error_id.0,
        object_type: m.object_info.object_type as u16,
        object_id: m.object_info.id,
        error_reaction: m.error_reaction as u8,
        warning_id: m.warning_id.0,
        external_setpoint_mode: m.external_setpoint_mode as u8,
        c_coordinate_mode: m.c_coordinate_mode as u8,
        x: m.set_pos.x,
        y: m.set_pos.y,
        z: m.set_pos.z,
        a: m.set_pos.a,
        b: m.set_pos.b,
        c: m.set_pos.c,
        velocity_x: m.set_velo.x,
        velocity_y: m.set_velo.y,
        velocity_z: m.set_velo.z,
        velocity_a: m.set_velo.a,
        velocity_b: m.set_velo.b,
        velocity_c: m.set_velo.c,
        acceleration_x: m.set_acc.x,
        acceleration_y: m.set_acc.y,
        acceleration_z: m.set_acc.z,
        acceleration_a: m.set_acc.a,
        acceleration_b: m.set_acc.b,
        acceleration_c: m.set_acc.c,
        ..Default::default()
    };
    crate::tracks::set_on_track(m, &mut out);
    out
}

/// The whole snapshot as `motion_msgs/PlanarState`.
pub fn planar_state(s: &Stamped<PlanarSnapshot>) -> PlanarState {
    let st = &s.state;
    let e = &st.environment;
    PlanarState {
        header: header(stamp(s)),
        environment: PlanarEnvironmentState {
            name: e.name.clone(),
            oid: e.oid,
            group_oid: e.group_oid,
            stator_count: e.stator_count as u32,
            boundary_element_count: e.boundary_element_count as u32,
            part_count: e.part_count as u32,
        },
        movers: st.movers.iter().map(mover_state).collect(),
        groups: st
            .groups
            .iter()
            .map(|g| PlanarGroupState {
                name: g.name.clone(),
                oid: g.oid,
                state: g.state as u8,
                movers: g.movers.clone(),
                environment_member: g.environment_member,
                tracks: g.tracks.clone(),
            })
            .collect(),
        parts: st
            .parts
            .iter()
            .map(|p| PlanarPartState {
                name: p.name.clone(),
                oid: p.oid,
                state: p.state as u8,
                position_index: p.position_index,
                coordinate_system_oid: p.position.reference_id,
                x: p.position.x,
                y: p.position.y,
                disable_forced: p.disable_forced,
                is_initialized: p.is_initialized,
                moving: p.moving,
            })
            .collect(),
        tracks: st.tracks.iter().map(crate::tracks::track_state).collect(),
        axes: st.axes.iter().map(crate::tracks::axis_state).collect(),
    }
}

/// Roll a, pitch b, yaw c \[deg\] (rotation z-y'-x'') as a quaternion.
fn quaternion(a: f64, b: f64, c: f64) -> Quaternion {
    motion_runtime::shell::quaternion_rpy(a.to_radians(), b.to_radians(), c.to_radians())
}

/// The pose of a mover's centre in metres: x, y, and z = lift (the top of the stators is 0).
fn mover_pose(m: &MoverSnapshot) -> Pose {
    let p = &m.set_pos;
    Pose {
        position: Point {
            x: p.x * MM,
            y: p.y * MM,
            z: p.z * MM,
        },
        orientation: quaternion(p.a, p.b, p.c),
    }
}

/// A header in the environment's frame [`FRAME_ID`] (poses in metres).
fn frame_header(t: Time) -> Header {
    Header {
        stamp: t,
        frame_id: FRAME_ID.to_string(),
    }
}

/// All movers as `geometry_msgs/PoseArray` (frame [`FRAME_ID`], metres; configuration order,
/// as in `~/state`).
pub fn mover_poses(s: &Stamped<PlanarSnapshot>) -> PoseArray {
    PoseArray {
        header: frame_header(stamp(s)),
        poses: s.state.movers.iter().map(mover_pose).collect(),
    }
}

fn color(r: f32, g: f32, b: f32, a: f32) -> ColorRGBA {
    ColorRGBA { r, g, b, a }
}

fn state_color(state: planar_engine::PlanarState) -> ColorRGBA {
    use planar_engine::PlanarState as S;
    match state {
        S::Enabled => color(0.1, 0.7, 0.2, 1.0),
        S::Error | S::ErrorPending => color(0.9, 0.1, 0.1, 1.0),
        S::Disabled | S::Invalid => color(0.5, 0.5, 0.5, 1.0),
        S::Enabling | S::Disabling | S::Resetting => color(0.9, 0.7, 0.1, 1.0),
    }
}

fn identity() -> Pose {
    Pose {
        position: Point::default(),
        orientation: Quaternion {
            x: 0.0,
            y: 0.0,
            z: 0.0,
            w: 1.0,
        },
    }
}

/// Outer edges of a set of tiles (one per exposed stator side, as the proposal's boundary
/// elements, xplanar.md §1.2), as point pairs in metres at height `z`.
fn boundary_lines(tiles: &[[f64; 2]], z: f64) -> Vec<Point> {
    let has = |x: f64, y: f64| {
        tiles
            .iter()
            .any(|t| (t[0] - x).abs() < 1e-6 && (t[1] - y).abs() < 1e-6)
    };
    let s = STATOR_SIDE;
    let mut out = Vec::new();
    let mut edge = |x0: f64, y0: f64, x1: f64, y1: f64| {
        out.push(Point {
            x: x0 * MM,
            y: y0 * MM,
            z,
        });
        out.push(Point {
            x: x1 * MM,
            y: y1 * MM,
            z,
        });
    };
    for &[x, y] in tiles {
        if !has(x, y - s) {
            edge(x, y, x + s, y);
        }
        if !has(x, y + s) {
            edge(x, y + s, x + s, y + s);
        }
        if !has(x - s, y) {
            edge(x, y, x, y + s);
        }
        if !has(x + s, y) {
            edge(x + s, y, x + s, y + s);
        }
    }
    out
}

/// The machine for RViz: stators as flat tiles (ns `stators`), the outer boundary (ns
/// `boundary`: orange while the environment is in a group, i.e. boundary checks are on,
/// grey otherwise), the tracks (ns `tracks`, [`crate::tracks::track_markers`]), each mover as a box of its configured size coloured by its state (ns
/// `movers`, id = configuration index) with its name above it (ns `mover_names`).
pub fn markers(geometry: &Geometry, s: &Stamped<PlanarSnapshot>) -> MarkerArray {
    let h = frame_header(stamp(s));
    let tiles = geometry.stators(&s.state);
    let mut out = Vec::with_capacity(2 + 2 * s.state.movers.len() + s.state.tracks.len());
    let action = |empty: bool| if empty { Marker::DELETE } else { Marker::ADD };
    out.push(Marker {
        header: h.clone(),
        ns: "stators".into(),
        id: 0,
        r#type: Marker::CUBE_LIST,
        action: action(tiles.is_empty()),
        pose: identity(),
        // 2 mm gaps between the tiles make the stator grid visible.
        scale: Vector3 {
            x: (STATOR_SIDE - 2.0) * MM,
            y: (STATOR_SIDE - 2.0) * MM,
            z: 0.01,
        },
        color: color(0.25, 0.27, 0.3, 1.0),
        points: tiles
            .iter()
            .map(|t| Point {
                x: (t[0] + STATOR_SIDE / 2.0) * MM,
                y: (t[1] + STATOR_SIDE / 2.0) * MM,
                z: -0.005,
            })
            .collect(),
        ..Default::default()
    });
    let checks_on = s.state.environment.group_oid != 0;
    let lines = boundary_lines(&tiles, 0.001);
    out.push(Marker {
        header: h.clone(),
        ns: "boundary".into(),
        id: 0,
        r#type: Marker::LINE_LIST,
        action: action(lines.is_empty()),
        pose: identity(),
        scale: Vector3 {
            x: 0.004,
            y: 0.0,
            z: 0.0,
        },
        color: if checks_on {
            color(1.0, 0.5, 0.0, 1.0)
        } else {
            color(0.7, 0.7, 0.7, 1.0)
        },
        points: lines,
        ..Default::default()
    });
    out.extend(crate::tracks::track_markers(&geometry.track_paths, s, &h));
    for (i, m) in s.state.movers.iter().enumerate() {
        let (w, hgt) = geometry
            .mover_sizes
            .get(i)
            .copied()
            .unwrap_or((155.0, 155.0));
        let mut pose = mover_pose(m);
        pose.position.z += MOVER_THICKNESS / 2.0 * MM;
        out.push(Marker {
            header: h.clone(),
            ns: "movers".into(),
            id: i as i32,
            r#type: Marker::CUBE,
            action: Marker::ADD,
            pose: pose.clone(),
            scale: Vector3 {
                x: w * MM,
                y: hgt * MM,
                z: MOVER_THICKNESS * MM,
            },
            color: state_color(m.state),
            ..Default::default()
        });
        pose.position.z += 0.04;
        pose.orientation = Quaternion {
            x: 0.0,
            y: 0.0,
            z: 0.0,
            w: 1.0,
        };
        out.push(Marker {
            header: h.clone(),
            ns: "mover_names".into(),
            id: i as i32,
            r#type: Marker::TEXT_VIEW_FACING,
            action: Marker::ADD,
            pose,
            scale: Vector3 {
                x: 0.0,
                y: 0.0,
                z: 0.04,
            },
            color: color(1.0, 1.0, 1.0, 1.0),
            text: m.name.clone(),
            ..Default::default()
        });
    }
    MarkerArray { markers: out }
}

pub(crate) fn register_topics(
    shell: &mut NodeShell<PlanarEngine>,
    geometry: Arc<Geometry>,
) -> Result<(), ShellError> {
    shell.state_publisher("~/state", PlanarState::type_name(), planar_state)?;
    shell.state_publisher("~/mover_poses", PoseArray::type_name(), mover_poses)?;
    shell.state_publisher("~/markers", MarkerArray::type_name(), move |s| {
        markers(&geometry, s)
    })?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use planar_engine::PlanarEngine;

    fn snapshot(yaml: &str) -> (Geometry, Stamped<PlanarSnapshot>) {
        let cfg: PlanarConfig = serde_yaml::from_str(yaml).unwrap();
        let g = Geometry::from_config(&cfg);
        let e = PlanarEngine::new(cfg).unwrap();
        (
            g,
            Stamped {
                cycle: 0,
                sim_time: 0.0,
                ros_time_ns: 0,
                state: motion_core::Engine::snapshot(&e),
            },
        )
    }

    const CFG: &str = "coordinate_systems: [0x01010060]
parts: [{name: table, oid: 0x01010020, tiles: [[0, 0], [240, 0], [0, 240], [240, 240]], positions: {1: {cs: 0x01010060, x: 0, y: 0}}}]
environment: {processing_unit_oid: 0x01010002}
movers: [{name: m1, initial_pose: {x: 120, y: 120, c: 90}, width: 155, height: 155}, {name: m2, initial_pose: {x: 360, y: 360}, width: 210, height: 155}]
";

    #[test]
    fn poses_are_in_metres_with_c_as_yaw() {
        let (_, s) = snapshot(CFG);
        let p = mover_poses(&s);
        assert_eq!(p.header.frame_id, FRAME_ID);
        assert_eq!(p.poses.len(), 2);
        assert!(
            (p.poses[0].position.x - 0.12).abs() < 1e-12
                && (p.poses[0].position.y - 0.12).abs() < 1e-12
        );
        let q = &p.poses[0].orientation;
        let half = std::f64::consts::FRAC_PI_4; // 90 deg yaw
        assert!(
            (q.z - half.sin()).abs() < 1e-12 && (q.w - half.cos()).abs() < 1e-12,
            "{q:?}"
        );
        assert!((p.poses[1].position.x - 0.36).abs() < 1e-12);
    }

    #[test]
    fn state_message_carries_names_states_and_units() {
        let (_, s) = snapshot(CFG);
        let m = planar_state(&s);
        assert_eq!(
            m.movers.iter().map(|m| m.name.as_str()).collect::<Vec<_>>(),
            ["m1", "m2"]
        );
        assert_eq!(m.movers[0].state, PlanarMoverState::STATE_DISABLED);
        assert_eq!(m.movers[0].command_mode, PlanarMoverState::MODE_INVALID);
        assert_eq!(
            (m.movers[0].x, m.movers[0].y, m.movers[0].c),
            (120.0, 120.0, 90.0)
        );
        assert_eq!(m.environment.stator_count, 4);
        assert_eq!(m.parts[0].name, "table");
        assert_eq!(m.parts[0].coordinate_system_oid, 0x01010060);
        assert_eq!(m.movers[0].part, "table");
    }

    /// §4.4 SET.SetAcc is in the mover state (issue 15 item 4), copied field by field.
    #[test]
    fn mover_state_carries_the_set_acceleration() {
        let (_, s) = snapshot(CFG);
        let mut m = s.state.movers[0].clone();
        m.set_acc.x = 1.5;
        m.set_acc.y = -2.5;
        m.set_acc.c = 30.0;
        let out = mover_state(&m);
        assert_eq!(
            (out.acceleration_x, out.acceleration_y, out.acceleration_c),
            (1.5, -2.5, 30.0)
        );
    }

    #[test]
    fn markers_show_stators_boundary_and_sized_movers() {
        let (g, s) = snapshot(CFG);
        let a = markers(&g, &s);
        let stators = &a.markers[0];
        assert_eq!(
            (stators.ns.as_str(), stators.r#type),
            ("stators", Marker::CUBE_LIST)
        );
        assert_eq!(stators.points.len(), 4);
        // A 2x2 block has 8 exposed stator sides (the §1.2 proposal's boundary elements).
        assert_eq!(a.markers[1].points.len(), 16);
        let m2 = a
            .markers
            .iter()
            .find(|m| m.ns == "movers" && m.id == 1)
            .unwrap();
        assert!((m2.scale.x - 0.21).abs() < 1e-12 && (m2.scale.y - 0.155).abs() < 1e-12);
        assert!(a
            .markers
            .iter()
            .any(|m| m.ns == "mover_names" && m.text == "m2"));
    }

    #[test]
    fn without_parts_the_added_stators_are_drawn() {
        let (g, s) = snapshot("movers: [{name: m1}]");
        let a = markers(&g, &s);
        assert_eq!(a.markers[0].action, Marker::DELETE);
        let mut e =
            PlanarEngine::new(serde_yaml::from_str("movers: [{name: m1}]").unwrap()).unwrap();
        use motion_core::Engine;
        e.command(planar_engine::PlanarCommand::AddStator {
            lower_x: 0.0,
            lower_y: 0.0,
        })
        .unwrap();
        e.command(planar_engine::PlanarCommand::AddStator {
            lower_x: 240.0,
            lower_y: 0.0,
        })
        .unwrap();
        let s = Stamped {
            cycle: 0,
            sim_time: 0.0,
            ros_time_ns: 0,
            state: e.snapshot(),
        };
        let a = markers(&g, &s);
        assert_eq!(a.markers[0].action, Marker::ADD);
        assert_eq!(a.markers[0].points.len(), 2);
        assert_eq!(a.markers[1].points.len(), 12); // 6 exposed sides
    }
}
