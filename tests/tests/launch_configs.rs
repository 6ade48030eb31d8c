//! Launch configs: every file in launch-configs/ passes `--check` with all node kinds, and a
//! wrong config names the file, the key and the problem, exiting with code 2 (issue 2 item 5).

use std::path::PathBuf;
use std::process::Command;

fn workspace() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("workspace")
        .to_path_buf()
}

fn launcher() -> PathBuf {
    let exe = std::env::current_exe().expect("test exe");
    let bin = exe
        .parent()
        .and_then(|d| d.parent())
        .expect("target dir")
        .join("motion_launch");
    assert!(
        bin.exists(),
        "{} missing: build the workspace first (scripts/test.sh does)",
        bin.display()
    );
    bin
}

#[test]
fn every_launch_config_checks_out() {
    let dir = workspace().join("launch-configs");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).expect("launch-configs") {
        let path = entry.expect("entry").path();
        if path.extension().and_then(|e| e.to_str()) != Some("yaml") {
            continue;
        }
        let entries = motion_runtime::launch::load(&path, motion_launch::KINDS)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(!entries.is_empty(), "{}: no nodes", path.display());
        for e in entries {
            let kind = motion_launch::KINDS
                .iter()
                .find(|k| k.kind == e.kind)
                .expect("kind");
            (kind.check)(&e.common, e.engine, &e.location).unwrap_or_else(|err| panic!("{err}"));
        }
        n += 1;
    }
    assert!(n >= 1, "no launch config found in {}", dir.display());
}

#[test]
fn demo_config_has_all_three_nodes() {
    let entries = motion_runtime::launch::load(
        &workspace().join("launch-configs/demo.yaml"),
        motion_launch::KINDS,
    )
    .unwrap();
    let kinds: Vec<&str> = entries.iter().map(|e| e.kind).collect();
    for k in ["axis_node", "planar_node", "pickplace_node"] {
        assert!(kinds.contains(&k), "demo.yaml lacks {k}: {kinds:?}");
    }
}

/// The demo's planar ring (tracks from the launch config, xplanar.md §1.6): four tracks
/// linked around the lower two rows of the table; m1 and m3 join it and ride half a lap on
/// opposite sides, as the demo driver (tests/peer/monitor.py) does.
#[test]
fn demo_planar_ring_carries_the_movers() {
    use motion_core::{CommandState, Engine, Tick};
    use planar_engine::{PlanarCommand, PlanarEngine};
    let entries = motion_runtime::launch::load(
        &workspace().join("launch-configs/demo.yaml"),
        motion_launch::KINDS,
    )
    .unwrap();
    let e = entries
        .into_iter()
        .find(|e| e.kind == "planar_node")
        .unwrap();
    let cfg = planar_node::config_from_yaml(e.engine, 0.001, &e.location).unwrap();
    let mut eng = PlanarEngine::new(cfg).unwrap();
    let ring = ["bottom", "right", "top", "left"];
    let run = |eng: &mut PlanarEngine, secs: f64, events: &mut Vec<_>| {
        for i in 0..(secs / 0.001) as u64 {
            eng.step(
                Tick {
                    index: i,
                    dt: 0.001,
                },
                events,
            );
        }
    };
    let mut events = vec![];
    for (k, t) in ring.iter().enumerate() {
        let s = eng.snapshot();
        let tr = s.track(t).unwrap();
        assert!(tr.length > 0.0, "{t} built");
        assert_eq!(tr.subsequent_tracks, vec![ring[(k + 1) % 4]], "{t} ring");
        eng.command(PlanarCommand::TrackEnable {
            track: t.to_string(),
        })
        .unwrap();
    }
    for m in ["m1", "m2", "m3", "m4"] {
        eng.command(PlanarCommand::MoverEnable { mover: m.into() })
            .unwrap();
    }
    run(&mut eng, 0.5, &mut events);
    for (m, t) in [("m1", "left"), ("m3", "bottom")] {
        eng.command(PlanarCommand::JoinTrack {
            mover: m.into(),
            track: t.into(),
            constraint: Default::default(),
            options: Default::default(),
        })
        .unwrap_or_else(|e| panic!("{m} joins {t}: {e}"));
    }
    run(&mut eng, 3.0, &mut events);
    // Two half laps: m1 and m3 swap sides, both driving forwards.
    for legs in [
        [("m1", "bottom", 180.0), ("m3", "top", 410.0)],
        [("m1", "top", 410.0), ("m3", "bottom", 180.0)],
    ] {
        let mut ids = vec![];
        for (m, t, x) in legs {
            let r = eng
                .command(PlanarCommand::MoveOnTrack {
                    mover: m.into(),
                    track: t.into(),
                    target_position: x,
                    constraint: Default::default(),
                    options: Default::default(),
                })
                .unwrap_or_else(|e| panic!("{m} to {t}: {e}"));
            ids.push((m, t, x, r.id));
        }
        events.clear();
        run(&mut eng, 6.0, &mut events);
        let s = eng.snapshot();
        for (m, t, x, id) in ids {
            let last = events.iter().rev().find(|e| e.id == id).map(|e| e.state);
            assert_eq!(last, Some(CommandState::Done), "{m} to {t}");
            let on = s.mover(m).unwrap().on_track.clone().expect("on track");
            assert_eq!(on.track, t, "{m}");
            assert!((on.set_pos - x).abs() < 0.1, "{m}: {on:?}");
        }
    }
}

/// Each bad config: (file text, what the message must name).
const BAD: &[(&str, &[&str])] = &[
    (
        "record: 5\nnodes:\n  - kind: axis_node\n    axes: {x: {}}\n",
        &["record", "expected a file name"],
    ),
    (
        "recrod: run.mcap\nnodes:\n  - kind: axis_node\n    axes: {x: {}}\n",
        &["recrod", "unknown key"],
    ),
    (
        "nodes:\n  - kind: axis_node\n    tf_pose: [0, 0, .nan, 0, 0, 0]\n    axes: {x: {}}\n",
        &["nodes[0] (axis_node).tf_pose", "NaN is not a finite number"],
    ),
    (
        "nodes:\n  - kind: planar_node\n    tf_parent: \"/world frame\"\n",
        &["tf_parent", "not a valid frame id"],
    ),
    (
        "nodes:\n  - kind: axis_node\n    lockstep: true\n    use_sim_time: true\n    axes: {x: {}}\n",
        &["use_sim_time", "exclude each other"],
    ),
    (
        "nodes:\n  - kind: axis_node\n    axes:\n      t: {joint_type: hinge}\n",
        &["axes.t.joint_type", "revolute"],
    ),
    (
        "nodes:\n  - kind: axis_node\n    axes:\n      x: {max_velocity: -5}\n",
        &["nodes[0] (axis_node)", "max_velocity", "-5"],
    ),
    (
        "nodes:\n  - kind: axis_node\n    axes:\n      x: {max_velo: 5}\n",
        &["axes.x", "unknown field `max_velo`"],
    ),
    (
        "nodes:\n  - kind: axis_node\n    cycle_period: .inf\n    axes: {x: {}}\n",
        &["cycle_period", "outside"],
    ),
    (
        "nodes:\n  - kind: axis_node\n    axes: {}\n",
        &["axes", "no axis"],
    ),
    (
        "nodes:\n  - kind: planar_nod\n",
        &["nodes[0].kind", "unknown node kind 'planar_nod'"],
    ),
    (
        "nodes:\n  - kind: axis_node\n    axes: {x: {}}\n    service_mapping: zenoh\n",
        &["service_mapping", "zenoh"],
    ),
    // Command scripts: the engine's command names and fields, finite non-negative times.
    (
        "nodes:\n  - kind: axis_node\n    axes: {x: {}}\n    script: [{at: 0, command: {MoveAbsolut: {axis: x}}}]\n",
        &["nodes[0] (axis_node).script[0].command", "unknown variant `MoveAbsolut`"],
    ),
    (
        "nodes:\n  - kind: planar_node\n    script: [{at: 0, command: {MoverEnable: {}}}]\n",
        &["nodes[0] (planar_node).script[0].command", "missing field `mover`"],
    ),
    (
        "nodes:\n  - kind: axis_node\n    axes: {x: {}}\n    script: [{at: .nan, command: {}}]\n",
        &["script[0].at", "outside"],
    ),
    (
        "nodes:\n  - kind: axis_node\n    axes: {x: {}}\n    script: [{at: -1, command: {}}]\n",
        &["script[0].at", "outside"],
    ),
    (
        "nodes:\n  - kind: pickplace_node\n    script: [{when: 1}]\n",
        &["script", "unknown field `when`"],
    ),
    // The live view: true, false or {host, port, page_port}.
    (
        "live: {port: 99999}\nnodes:\n  - kind: axis_node\n    axes: {x: {}}\n",
        &["live", "99999"],
    ),
    (
        "live: {prot: 8765}\nnodes:\n  - kind: axis_node\n    axes: {x: {}}\n",
        &["live", "unknown field `prot`"],
    ),
    (
        "nodes:\n  - kind: planar_node\n    tracks: [{name: t, geometry: [{line: {start: [0, 0], end: [0, 0]}}]}]\n",
        &["nodes[0] (planar_node)", "0x4A0A", "E_GEOMETRY_INVALID", "tracks[0].geometry[0]", "track 't'"],
    ),
];

#[test]
fn bad_configs_exit_2_naming_file_key_and_problem() {
    let dir = std::env::temp_dir().join(format!("motion_bad_configs_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (i, (text, needles)) in BAD.iter().enumerate() {
        let file = dir.join(format!("bad{i}.yaml"));
        std::fs::write(&file, text).unwrap();
        let out = Command::new(launcher())
            .arg(&file)
            .arg("--check")
            .output()
            .expect("run motion_launch");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{text:?}: {err}");
        assert!(
            err.contains(&*file.to_string_lossy()),
            "{text:?}: file not named: {err}"
        );
        for n in *needles {
            assert!(err.contains(n), "{text:?}: '{n}' not in: {err}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--ros-args` as ROS users pass them: `-p` overrides go through the config's validation
/// (a bad value exits 2 naming the key), `--params-file` in ROS form works, anything else
/// after `--ros-args` is a clear error with exit code 2.
#[test]
fn ros_args_overrides_are_validated_and_unknown_ones_refused() {
    let dir = std::env::temp_dir().join(format!("motion_ros_args_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cfg = dir.join("c.yaml");
    std::fs::write(&cfg, "nodes:\n  - kind: axis_node\n    axes: {x: {}}\n").unwrap();
    let params = dir.join("p.yaml");
    std::fs::write(
        &params,
        "/axis_node:\n  ros__parameters:\n    axes:\n      x: {max_velocity: -3.0}\n",
    )
    .unwrap();
    let run = |args: &[&str]| {
        let out = Command::new(launcher())
            .arg(&cfg)
            .arg("--check")
            .args(args)
            .output()
            .expect("run motion_launch");
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stderr).to_string(),
        )
    };
    let (code, err) = run(&["--ros-args", "-p", "state_rate:=25.0", "-r", "__node:=arm"]);
    assert_eq!(code, Some(0), "{err}");
    let (code, err) = run(&["--ros-args", "-p", "cycle_period:=-1.0"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("cycle_period") && err.contains("outside"),
        "{err}"
    );
    let (code, err) = run(&["--ros-args", "-p", "axis_node:axes.x.jerk:=.nan"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("jerk"), "{err}");
    let (code, err) = run(&["--ros-args", "--params-file", params.to_str().unwrap()]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("max_velocity") && err.contains("-3"), "{err}");
    let (code, err) = run(&["--ros-args", "--enclave", "/x"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("unsupported argument '--enclave'"), "{err}");
    let (code, err) = run(&["--ros-args", "-p", "no_assignment"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains(":="), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
