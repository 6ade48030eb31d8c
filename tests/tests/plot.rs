//! `motion_plot` on recordings as users make them (issue 14 item 5): the demo machine moving by
//! its script and the collision-avoidance ring, each run with `motion_launch --cycles N
//! --record`, then plotted. Every figure must come out as PNG and SVG with its labels, units
//! and legend; the figures of the demo run stay in `target/plots/` for people to look at.

use std::path::Path;
use std::process::Command;
use system_tests::{launcher_bin, moving_demo, require_netns, unique_domain, workspace};

fn plot_bin() -> std::path::PathBuf {
    launcher_bin().with_file_name("motion_plot")
}

/// Runs `config` for `cycles` lockstep cycles, recorded to `dir/run.mcap`, then plots it into
/// `out`; returns motion_plot's stdout.
fn record_and_plot(dir: &Path, config: &str, cycles: u32, out: &Path) -> String {
    std::fs::create_dir_all(dir).unwrap();
    let file = dir.join("config.yaml");
    std::fs::write(&file, config).unwrap();
    let mcap = dir.join("run.mcap");
    let run = Command::new(launcher_bin())
        .arg(&file)
        .args(["--no-live", "--cycles", &cycles.to_string(), "--record"])
        .arg(&mcap)
        .env("ROS_DOMAIN_ID", unique_domain().to_string())
        .env("RUST_LOG", "warn,rustdds=error,ros2_client=error")
        .output()
        .expect("motion_launch");
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let plot = Command::new(plot_bin())
        .arg(&mcap)
        .arg("--out")
        .arg(out)
        .output()
        .expect("motion_plot");
    let stdout = String::from_utf8_lossy(&plot.stdout).into_owned();
    assert!(
        plot.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&plot.stderr)
    );
    stdout
}

/// The figure `stem` exists as a PNG of at least `min` pixels each way and as an SVG that
/// carries every text of `texts` (labels, units, legend entries).
fn check_figure(out: &Path, stem: &str, min: (u32, u32), texts: &[&str]) {
    let png = std::fs::read(out.join(format!("{stem}.png")))
        .unwrap_or_else(|e| panic!("{stem}.png: {e}"));
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n", "{stem}.png");
    // IHDR: width and height, big endian, at bytes 16..24.
    let w = u32::from_be_bytes(png[16..20].try_into().unwrap());
    let h = u32::from_be_bytes(png[20..24].try_into().unwrap());
    assert!(w >= min.0 && h >= min.1, "{stem}.png is {w}x{h}");
    let svg = std::fs::read_to_string(out.join(format!("{stem}.svg"))).unwrap();
    assert!(svg.starts_with("<svg"), "{stem}.svg");
    for t in texts {
        assert!(svg.contains(t), "{stem}.svg lacks '{t}'");
    }
}

#[test]
fn every_figure_of_the_demo_and_the_ca_ring() {
    require_netns();
    let tmp = std::env::temp_dir().join(format!("motion_plot_{}", std::process::id()));
    let out = workspace().join("target/plots");
    let _ = std::fs::remove_dir_all(&out);
    let said = record_and_plot(
        &tmp.join("demo"),
        &moving_demo::config(3.0, None, true),
        3000,
        &out,
    );
    assert!(said.contains("3 axes, 4 movers"), "{said}");
    // The script's commands carry their axis: table's MoveVelocity Active, x's first
    // MoveAbsolute Active and Done, its second (at 2.01 s) Active.
    let events: u32 = said
        .lines()
        .next()
        .unwrap_or_default()
        .split(", ")
        .find_map(|p| p.strip_suffix(" command events on the axes"))
        .and_then(|n| n.trim().parse().ok())
        .unwrap_or_else(|| panic!("{said}"));
    assert!(events >= 4, "{said}");
    check_figure(
        &out,
        "axes",
        (1000, 700),
        &[
            "time [s]",
            "SetPos [u]",
            "SetVelo [u/s]",
            "SetAcc [u/s²]",
            "x SetPos",
            "table SetVelo",
            "Active",
        ],
    );
    check_figure(
        &out,
        "planar_trails",
        (800, 600),
        &["x [mm]", "y [mm]", "m2", "m4", "tracks"],
    );
    check_figure(
        &out,
        "pickplace_tcp",
        (1000, 400),
        &["XY projection", "z [mm]", "TCP"],
    );
    check_figure(
        &out,
        "cycle_times",
        (1000, 600),
        // The last statistics count every cycle of the run.
        &[
            "execution time [µs]",
            "cycles",
            "axis_node: execution time, 3000 cycles",
            "planar_node",
            "pickplace_node",
        ],
    );
    // The demo has no CA group; the ring has one.
    assert!(!out.join("ca_gaps.png").exists());
    let ring = out.join("ca_ring");
    let said = record_and_plot(
        &tmp.join("ring"),
        &moving_demo::ca_ring_config(),
        4000,
        &ring,
    );
    assert!(said.contains("1 CA groups"), "{said}");
    check_figure(
        &ring,
        "ca_gaps",
        (1000, 300),
        &["group ring", "gap [mm]", "m3 gap", "m3 target", "time [s]"],
    );
    let _ = std::fs::remove_dir_all(&tmp);
}

/// Bad input: a missing file, a file that is no MCAP, no file: exit code 2 with a message.
#[test]
fn bad_recordings_are_refused_with_a_message() {
    let tmp = std::env::temp_dir().join(format!("motion_plot_bad_{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    std::fs::write(tmp.join("junk.mcap"), b"not an mcap file").unwrap();
    for (args, needle) in [
        (
            vec![tmp.join("missing.mcap").display().to_string()],
            "missing.mcap",
        ),
        (
            vec![tmp.join("junk.mcap").display().to_string()],
            "not a readable MCAP file",
        ),
        (vec![], "usage: motion_plot"),
        (vec!["--bogus".to_string()], "unknown option --bogus"),
    ] {
        let out = Command::new(plot_bin())
            .args(&args)
            .output()
            .expect("motion_plot");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
    let _ = std::fs::remove_dir_all(&tmp);
}
