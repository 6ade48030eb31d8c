//! Track geometry from the init parameters (xplanar.md §1.6, V3.1.10.44): "Starts from
//! tracks", "Geometric information", "Ends at tracks" and "Closed loop" of the
//! configuration "act exactly like the corresponding PLC commands", so they are applied at
//! start-up as exactly those engine commands (§3.3). Points are given in the system of the
//! track's part (V3.2.60).
//!
//! Order: per track its `starts_from`, `geometry`, `ends_at`, `closed_loop`, as a PLC program
//! would call them. Across tracks a call waits until the track it refers to is ready: a
//! StartFromTrack until the other track's end is final (all its calls done), an EndAtTrack until
//! the other track's start exists. Tracks are visited in configuration order until nothing
//! is left; what still waits then refers in a circle (an error, as in the PLC). A track
//! that does not lie completely on its part (refused by Enable, §5.4) is refused at load.

use crate::command::PlanarCommand;
use crate::config::{PlanarConfig, TrackGeometryItem, TrackLinkConfig};
use crate::engine::PlanarEngine;
use crate::errors::{reject, E_GEOMETRY_INVALID};
use crate::track::TrackLinkAdvancedOptions;
use crate::types::PositionXYC;
use motion_core::{Engine, Rejection};

/// What a call needs of the other track before it can run.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Wait {
    Nothing,
    /// The other track's calls are all done (its end is final).
    Finished(usize),
    /// The other track has a start point (non-empty geometry) or is finished.
    Started(usize),
}

/// One init-parameter call: config key, the command, what it waits for.
struct Call {
    key: String,
    cmd: PlanarCommand,
    wait: Wait,
}

/// A load-time error: the spec's id, the key of the offending entry and the track.
fn at(key: &str, track: &str, r: Rejection) -> Rejection {
    Rejection::new(
        r.error_id,
        format!("config {key} (track '{track}'): {}", r.message),
    )
}

fn link_command(track: &str, start: bool, link: &TrackLinkConfig) -> (String, PlanarCommand) {
    let track = track.to_string();
    match link {
        TrackLinkConfig::Plain(other) => (
            other.clone(),
            if start {
                PlanarCommand::TrackStartFromTrack {
                    track,
                    other: other.clone(),
                }
            } else {
                PlanarCommand::TrackEndAtTrack {
                    track,
                    other: other.clone(),
                }
            },
        ),
        TrackLinkConfig::Advanced(a) => {
            let options = TrackLinkAdvancedOptions {
                this_track_part_position_index: a.this_track_part_position_index,
                other_track_part_position_index: a.other_track_part_position_index,
                link_only_in_specified_part_positions: a.link_only_in_specified_part_positions,
            };
            let other = a.track.clone();
            (
                other.clone(),
                if start {
                    PlanarCommand::TrackStartFromTrackAdvanced {
                        track,
                        other,
                        options,
                    }
                } else {
                    PlanarCommand::TrackEndAtTrackAdvanced {
                        track,
                        other,
                        options,
                    }
                },
            )
        }
    }
}

fn geometry_command(track: &str, refid: u32, item: &TrackGeometryItem) -> PlanarCommand {
    let pt = |p: [f64; 2]| PositionXYC::with_ref(p[0], p[1], 0.0, refid);
    let track = track.to_string();
    match *item {
        TrackGeometryItem::Position(q) => PlanarCommand::TrackAppendPosition {
            track,
            position: PositionXYC::with_ref(q.x, q.y, q.c, refid),
        },
        TrackGeometryItem::Line(l) => PlanarCommand::TrackAppendLine {
            track,
            start: pt(l.start),
            end: pt(l.end),
        },
        TrackGeometryItem::Circle(c) => PlanarCommand::TrackAppendCircle {
            track,
            start: pt(c.start),
            end: pt(c.end),
            center: pt(c.center),
            clockwise: c.clockwise,
        },
    }
}

/// The calls of track `k` in program order.
fn calls_of(eng: &PlanarEngine, cfg: &PlanarConfig, k: usize) -> Result<Vec<Call>, Rejection> {
    let t = &cfg.tracks[k];
    let key = format!("tracks[{k}]");
    let has_init = !(t.starts_from.is_empty()
        && t.geometry.is_empty()
        && t.ends_at.is_empty()
        && !t.closed_loop);
    if has_init && cfg.parts.len() > 1 && t.part_oid == 0 {
        return Err(at(
            &format!("{key}.part_oid"),
            &t.name,
            reject(
                E_GEOMETRY_INVALID,
                "PartOID required when more than one part exists",
            ),
        ));
    }
    let mut calls = Vec::new();
    for (start, list, field) in [
        (true, &t.starts_from, "starts_from"),
        (false, &t.ends_at, "ends_at"),
    ] {
        for (j, link) in list.iter().enumerate() {
            let key = format!("{key}.{field}[{j}]");
            let (other, cmd) = link_command(&t.name, start, link);
            let o = eng.tracks.track(&other).map_err(|r| at(&key, &t.name, r))?;
            let wait = match (o == k, start) {
                (true, _) => Wait::Nothing,
                (false, true) => Wait::Finished(o),
                (false, false) => Wait::Started(o),
            };
            calls.push(Call { key, cmd, wait });
        }
        if start {
            // The geometry lies between the two kinds of links.
            let refid = eng.tracks.tracks[k].part_oid;
            for (j, item) in t.geometry.iter().enumerate() {
                calls.push(Call {
                    key: format!("{key}.geometry[{j}]"),
                    cmd: geometry_command(&t.name, refid, item),
                    wait: Wait::Nothing,
                });
            }
        }
    }
    if t.closed_loop {
        calls.push(Call {
            key: format!("{key}.closed_loop"),
            cmd: PlanarCommand::TrackCloseLoop {
                track: t.name.clone(),
            },
            wait: Wait::Nothing,
        });
    }
    Ok(calls)
}

/// Builds the configured tracks' geometry and links; the first failing call is the error
/// (its id is the command's, the message names the key and the track).
pub(crate) fn apply(eng: &mut PlanarEngine, cfg: &PlanarConfig) -> Result<(), Rejection> {
    let calls = (0..cfg.tracks.len())
        .map(|k| calls_of(eng, cfg, k))
        .collect::<Result<Vec<_>, _>>()?;
    let mut next = vec![0usize; calls.len()];
    loop {
        let mut progress = false;
        for k in 0..calls.len() {
            while let Some(c) = calls[k].get(next[k]) {
                let ready = match c.wait {
                    Wait::Nothing => true,
                    Wait::Finished(o) => next[o] == calls[o].len(),
                    Wait::Started(o) => {
                        next[o] == calls[o].len() || !eng.tracks.tracks[o].geo.is_empty()
                    }
                };
                if !ready {
                    break;
                }
                eng.command(c.cmd.clone())
                    .map_err(|r| at(&c.key, &cfg.tracks[k].name, r))?;
                next[k] += 1;
                progress = true;
            }
        }
        if !progress {
            break;
        }
    }
    if let Some(k) = (0..calls.len()).find(|&k| next[k] < calls[k].len()) {
        let c = &calls[k][next[k]];
        let o = match c.wait {
            Wait::Finished(o) | Wait::Started(o) => o,
            Wait::Nothing => k,
        };
        return Err(at(
            &c.key,
            &cfg.tracks[k].name,
            reject(
                E_GEOMETRY_INVALID,
                format!(
                    "waits for track '{}', whose geometry waits for this track (circular links)",
                    cfg.tracks[o].name
                ),
            ),
        ));
    }
    // Enable would refuse a track off its part; a configured one is refused at load.
    for (k, t) in cfg.tracks.iter().enumerate() {
        if !eng.tracks.tracks[k].geo.is_empty() {
            eng.tracks
                .track_lies_on_part(&eng.objects, k)
                .map_err(|r| at(&format!("tracks[{k}].geometry"), &t.name, r))?;
        }
    }
    // The start-up calls are not commands of anybody: no events, ids start at 1.
    eng.objects.pending.clear();
    eng.objects.next_id = 1;
    Ok(())
}
