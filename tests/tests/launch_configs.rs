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
            (kind.check)(e.engine, &e.location).unwrap_or_else(|err| panic!("{err}"));
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

/// Each bad config: (file text, what the message must name).
const BAD: &[(&str, &[&str])] = &[
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
