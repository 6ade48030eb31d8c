//! `lockstep` (issue 14 item 4): the axis node with 10 moving axes in lockstep, every cycle's
//! state published and recorded to MCAP, stepped in-process (as `motion_launch --cycles`
//! does), as a ratio of simulated to wall time; the references are the bare engine stepping the
//! same motion, the node with nothing recorded (its stream of snapshots alone), and the
//! recording's floor (its bytes written again with nothing else to do), all in the same run.
//! Must run inside scripts/netns-run (the node opens DDS sockets).

use axis_engine::MoveVelocity;
use axis_engine::{AxisCommand, AxisConfig, AxisEngine, BufferMode, Direction, MoveOptions};
use motion_core::{Engine, Tick};
use motion_runtime::host::CommonConfig;
use motion_runtime::launch::Running;
use motion_runtime::record::Compression;
use std::time::Instant;

const AXES: usize = 10;
const TARGET: f64 = 1000.0;

/// Power and MoveVelocity of axis `a{i}` (also the live bench's motion).
pub(crate) fn orders(i: usize) -> [AxisCommand; 2] {
    let axis = format!("a{i}");
    [
        system_tests::moving_demo::power(&axis),
        AxisCommand::MoveVelocity(MoveVelocity {
            axis,
            // Within the default limit (2000 u/s) for any count of axes.
            velocity: 100.0 + 10.0 * (i % 190) as f64,
            acceleration: 0.0,
            deceleration: 0.0,
            jerk: 0.0,
            direction: Direction::Positive,
            buffer_mode: BufferMode::Aborting,
            options: MoveOptions::default(),
        }),
    ]
}

/// An axis node named `axis_node` with axes `a0` … (default configuration each), in lockstep
/// or real time at 1 kHz, on `domain_id`.
pub(crate) fn axis_node_of(
    axes: usize,
    lockstep: bool,
    location: &str,
    domain_id: u16,
) -> axis_node::AxisNode {
    let common = CommonConfig {
        name: "axis_node".into(),
        lockstep,
        ..Default::default()
    };
    let names: Vec<String> = (0..axes).map(|i| format!("a{i}: {{}}")).collect();
    let cfg = serde_yaml::from_str(&format!("axes: {{{}}}", names.join(", "))).expect("yaml");
    axis_node::start(&common, cfg, location, domain_id).expect("node")
}

/// How many of the node's axes move (positive set velocity) in its latest snapshot.
pub(crate) fn moving(h: &motion_runtime::ControllerHandle<axis_engine::AxisEngine>) -> usize {
    h.snapshot()
        .state
        .axes
        .iter()
        .filter(|a| a.set_velo > 0.0)
        .count()
}

/// The bare engine: `count` axes given [`orders`], stepped `cycles` times, with (`snapshots`)
/// or without the engine's snapshot of every cycle (refilled in place, as the node's stream
/// does); simulated / wall time.
pub(crate) fn bare(count: usize, cycles: u64, snapshots: bool) -> f64 {
    let axes = (0..count)
        .map(|i| (format!("a{i}"), AxisConfig::default()))
        .collect();
    let mut e = AxisEngine::new(axes).expect("engine");
    let mut ev = Vec::new();
    let mut tick = 0;
    let mut step = |e: &mut AxisEngine| {
        e.step(
            Tick {
                index: tick,
                dt: 0.001,
            },
            &mut ev,
        );
        tick += 1;
        ev.clear();
    };
    for k in 0..2 {
        for i in 0..count {
            e.command(orders(i)[k].clone()).expect("order");
        }
        step(&mut e);
        step(&mut e);
    }
    let mut snapshot = e.snapshot();
    let t0 = Instant::now();
    for _ in 0..cycles {
        step(&mut e);
        if snapshots {
            e.snapshot_into(&mut snapshot);
            std::hint::black_box(&snapshot);
        }
    }
    cycles as f64 * 0.001 / t0.elapsed().as_secs_f64()
}

/// The node stepped `cycles` in lockstep, every cycle recorded (`record_only`: not written to
/// DDS, as `motion_launch --cycles` does); (x real time, axes moving).
fn node_speed(rt: &tokio::runtime::Runtime, cycles: u64, record_only: bool) -> (f64, usize) {
    motion_runtime::record::set_record_only(record_only);
    rt.block_on(async {
        let node = axis_node_of(AXES, true, "bench lockstep", 152);
        let h = node.handle();
        for k in 0..2 {
            let replies: Vec<_> = (0..AXES)
                .map(|i| h.submit(orders(i)[k].clone(), None).expect("queued"))
                .collect();
            h.step(2).await.expect("step");
            for r in replies {
                r.await.expect("reply").expect("order accepted");
            }
        }
        let t0 = Instant::now();
        let c = h.step(cycles).await.expect("step");
        node.flush(c).await;
        let wall = t0.elapsed().as_secs_f64();
        let moving = moving(&h);
        Box::new(node).stop().await;
        (cycles as f64 * 0.001 / wall, moving)
    })
}

/// The floor a recording sets (the reference for the 1 000x goal): the first `cycles` cycles
/// of the recording in `file`, written again, message by message, by the same MCAP writer
/// (no engine, no message building, no serializing), uncompressed (the default of `--record`)
/// and with zstd (`--record-compression zstd`), and their bytes written to a plain file.
fn floor(file: &std::path::Path, cycles: u64) -> Floor {
    use std::io::{Read, Write};
    // Enough of the file for `cycles` cycles (the recording is longer; its end is not read).
    let mut bytes = Vec::new();
    std::fs::File::open(file)
        .and_then(|f| f.take(400 << 20).read_to_end(&mut bytes))
        .expect("recording readable");
    let opts = mcap::read::Options::IgnoreEndMagic.into();
    let mut messages = Vec::new();
    let mut first = None;
    for m in mcap::MessageStream::new_with_options(&bytes, opts).expect("mcap") {
        let Ok(m) = m else { break };
        let t0 = *first.get_or_insert(m.log_time);
        if m.log_time >= t0 + cycles * 1_000_000 {
            break;
        }
        let ty = m
            .channel
            .schema
            .as_ref()
            .map_or(String::new(), |s| s.name.clone());
        messages.push((m.channel.topic.clone(), ty, m.log_time, m.data.into_owned()));
    }
    let total: usize = messages.iter().map(|m| m.3.len()).sum();
    let out = std::env::temp_dir().join(format!("bench_floor_{}.mcap", std::process::id()));
    // (seconds, file size) of the MCAP writer.
    let write = |compression| {
        let t0 = Instant::now();
        let mut rec =
            motion_runtime::record::Recording::create(&out, compression).expect("floor file");
        for (topic, ty, t, data) in &messages {
            rec.write_cdr(topic, ty, *t, data).expect("written");
        }
        rec.finish().expect("closed");
        let took = t0.elapsed().as_secs_f64();
        (
            took,
            std::fs::metadata(&out).expect("floor file").len() as f64,
        )
    };
    let (writer, size) = write(Compression::None);
    let (zstd, zstd_size) = write(Compression::Zstd);
    let t0 = Instant::now();
    let mut f = std::io::BufWriter::with_capacity(
        motion_runtime::record::WRITE_BUFFER,
        std::fs::File::create(&out).expect("floor file"),
    );
    for (_, _, _, data) in &messages {
        f.write_all(data).expect("written");
    }
    f.flush().expect("written");
    drop(f);
    let plain = t0.elapsed().as_secs_f64();
    let _ = std::fs::remove_file(&out);
    let sim = cycles as f64 * 0.001;
    Floor {
        per_cycle: total as f64 / cycles as f64,
        writer: sim / writer,
        zstd: sim / zstd,
        zstd_smaller: size / zstd_size,
        plain: sim / plain,
    }
}

/// The recording's floor (see [`floor`]): bytes per cycle, and each way of writing them as x
/// real time.
struct Floor {
    per_cycle: f64,
    writer: f64,
    zstd: f64,
    /// The uncompressed file's size / the zstd file's.
    zstd_smaller: f64,
    plain: f64,
}

pub fn speed(cycles: u64) {
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .expect("rt");
    // Before the recording starts: the same run with nobody taking any topic (every cycle's
    // snapshot still streamed), the node's own ceiling.
    let (unrecorded, _) = node_speed(&rt, cycles, true);
    let file = std::env::temp_dir().join(format!("bench_lockstep_{}.mcap", std::process::id()));
    // Uncompressed (the default): the fastest; zstd's cost is in the floor.
    motion_runtime::record::start(
        &file,
        motion_runtime::record::Topics::all(),
        Compression::None,
    )
    .expect("recording");
    let (published, _) = node_speed(&rt, cycles, false);
    let (ratio, moving) = node_speed(&rt, cycles, true);
    motion_runtime::record::set_record_only(false);
    let (written, dropped) = motion_runtime::record::finish()
        .expect("recording on")
        .expect("recording closed");
    let Floor {
        per_cycle,
        writer,
        zstd,
        zstd_smaller,
        plain,
    } = floor(&file, cycles.min(20_000));
    let _ = std::fs::remove_file(&file);
    let bare_snapshots = bare(AXES, cycles, true);
    let bare = bare(AXES, cycles, false);
    println!(
        "lockstep @1 ms, axis node, {moving} of {AXES} axes moving, every cycle recorded (uncompressed): {ratio:.1}x real time recorded only (as --cycles runs) | {published:.1}x also published over DDS ({written} messages, {dropped} dropped) | {unrecorded:.1}x with nothing recorded | bare engine {bare:.0}x (ratio {:.4}), with a snapshot per cycle {bare_snapshots:.0}x | target >= {TARGET:.0}x: {}",
        ratio / bare,
        if ratio >= TARGET { "met" } else { "NOT met" }
    );
    println!(
        "lockstep recording floor: {:.1} KB per cycle (files in {}, TMPDIR: a disk scatters the figures, tmpfs does not); writing them again, nothing else: MCAP writer {writer:.0}x real time (node/writer {:.2}), with zstd {zstd:.0}x and {zstd_smaller:.1}x smaller, plain file {plain:.0}x (node/file {:.2}); {TARGET:.0}x needs {:.1} GB/s",
        per_cycle / 1e3,
        std::env::temp_dir().display(),
        ratio / writer,
        ratio / plain,
        per_cycle * TARGET * 1e3 / 1e9,
    );
}
