//! The user guide (`docs/*.md`, issue 15.13) is complete and current: its generated tables
//! (launch-config keys with defaults, error ids) equal what the code says now, and every
//! configuration key, error id and config struct named there exists. Its `ros2` examples run
//! in `tests/rclpy/test_readme.py`.

use system_tests::{docs, workspace};

#[test]
fn the_guide_is_current_with_the_code() {
    let stale: Vec<String> = docs::render(&workspace())
        .into_iter()
        .filter(|(_, old, new)| old != new)
        .map(|(p, _, _)| p.display().to_string())
        .collect();
    assert!(
        stale.is_empty(),
        "stale pages (run `cargo run -p system_tests --bin gen_docs`): {stale:?}"
    );
}

#[test]
fn every_page_has_its_tables_and_the_readme_links_the_guide() {
    let root = workspace();
    let page = |p: &str| std::fs::read_to_string(root.join("docs").join(p)).unwrap();
    for (p, parts) in [
        ("README.md", &["keys-common", "errors-common"][..]),
        (
            "axis_node.md",
            &[
                "keys-axis",
                "keys-axis-platform",
                "keys-axis-ca",
                "errors-axis",
                "errors-axis-ca",
                "errors-axis-platform",
            ][..],
        ),
        ("planar_node.md", &["keys-planar", "errors-planar"][..]),
        (
            "pickplace_node.md",
            &["keys-pickplace", "errors-pickplace"][..],
        ),
    ] {
        let text = page(p);
        for part in parts {
            assert!(
                text.contains(&format!("<!-- BEGIN GENERATED {part} -->")),
                "{p} lacks {part}"
            );
        }
        // Worked examples or services of every node page are in `ros2`/table form.
        assert!(text.contains("| key | default | meaning |"), "{p}");
    }
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    for p in [
        "docs/README.md",
        "docs/axis_node.md",
        "docs/planar_node.md",
        "docs/pickplace_node.md",
    ] {
        assert!(
            readme.contains(&format!("]({p})")),
            "README does not link {p}"
        );
    }
    assert!(
        !readme.contains("../shared/"),
        "the README must not point outside the repository"
    );
    // Spot checks that the generated tables carry real values, not placeholders.
    let axis = page("axis_node.md");
    assert!(
        axis.contains("| `axes.<axis>.max_velocity` | 2000.0 |"),
        "axis defaults"
    );
    assert!(
        axis.contains("| 19201 | 0x4B01 | `AXIS_CANNOT_BE_STARTED` |"),
        "axis ids"
    );
    let planar = page("planar_node.md");
    assert!(
        planar.contains("| 18949 | 0x4A05 | `E_COLLISION` |"),
        "planar ids"
    );
    assert!(
        planar.contains("| `movers[].width` | 155.0 |"),
        "mover defaults"
    );
}

/// Every launch config shown in the README and the guide (```yaml blocks with `nodes:`) is
/// accepted as written, node part included, as `motion_launch --check` would.
#[test]
fn the_launch_configs_shown_are_valid() {
    let root = workspace();
    let mut pages = vec![root.join("README.md")];
    for e in std::fs::read_dir(root.join("docs")).unwrap() {
        let path = e.unwrap().path();
        if path.extension().is_some_and(|x| x == "md") {
            pages.push(path);
        }
    }
    let mut checked = 0;
    for page in pages {
        let text = std::fs::read_to_string(&page).unwrap();
        for block in text.split("```yaml\n").skip(1) {
            let yaml = block.split("```").next().unwrap();
            if !yaml.contains("nodes:") {
                continue;
            }
            let file = page.display().to_string();
            let entries = motion_runtime::launch::parse(yaml, &file, motion_launch::KINDS)
                .unwrap_or_else(|e| panic!("{file}: {e}"));
            for e in entries {
                let kind = motion_launch::KINDS
                    .iter()
                    .find(|k| k.kind == e.kind)
                    .expect("kind");
                (kind.check)(&e.common, e.engine.clone(), &e.location)
                    .unwrap_or_else(|e| panic!("{e}"));
            }
            checked += 1;
        }
    }
    assert!(
        checked >= 2,
        "the README and docs/README.md show launch configs"
    );
}
