//! `~/events` (plcopen_platform.md §12.1): one reliable, keep-all stream of
//! `motion_msgs/AxisEvent` with
//! - acknowledgements of the orders of `~/command_status` (ACCEPTED, for a buffered order
//!   ACTIVE when it takes over, then DONE, ABORTED or ERROR), from the runtime's command event
//!   tap, in the order `~/command_status` has them;
//! - MC errors and warnings: new entries of each axis' MC message buffer (§7.2, with remedy and
//!   reaction class), and in the `tc2_mc2` profile an axis error code that appears without one;
//! - clog warnings 4906 of the raw FB layer (R-HS-5);
//! - safety events (§8): operating mode, enabling switch, START button, and per axis feed
//!   hold, velocity / torque-limit monitoring (leases), torque limiting, referencing.
//!
//! The MC messages, clog warnings and safety states are compared between consecutive
//! snapshots at the state rate, so the cycle is never blocked; the snapshot keeps 6 messages
//! per axis and the last 8 clog warnings, more than arrive between two samples in practice.
//! In lockstep with a state stream (recording, `--cycles`) every streamed cycle is compared
//! with the one before, and each cycle's acknowledgements come before its state changes:
//! the same events, stamps and numbers on every run.

use axis_engine::platform::{AxisSafetyStatus, McMessage, PlatformStatus};
use axis_engine::{AxisEngine, AxisSnapshot};
use motion_core::{CommandEvent, CommandState, Engine};
use motion_msgs::deps::builtin_interfaces::msg::Time;
use motion_msgs::msg::AxisEvent;
use motion_runtime::cycle::Stamped;
use motion_runtime::shell::{private_name, stamp, stamp_ns};
use motion_runtime::{CommandLabel, NodeShell, ShellError};
use ros2_client::qos::{Durability, History, QosProfile};
use std::time::Duration;

/// Reliable, keep-all (nothing is dropped for a slow reader), volatile.
fn events_qos() -> QosProfile {
    QosProfile::publisher_default()
        .durability(Durability::Volatile)
        .history(History::KeepAll)
}

/// What changed between two snapshots, as events (without stamp and sequence number). The
/// axes (and the platform's per-axis entries, when present) are in configuration order in
/// every snapshot, so they are compared by index.
pub fn diff(prev: &AxisSnapshot, next: &AxisSnapshot) -> Vec<AxisEvent> {
    let mut out = Vec::new();
    let (p, n) = (&prev.platform, &next.platform);
    safety_changes(p, n, &mut out);
    for (k, a) in next.axes.iter().enumerate() {
        let fresh = match n.axes.get(k) {
            Some(s) => new_messages(p.axes.get(k).map_or(&[], |o| &o.messages), &s.messages),
            None => &[],
        };
        for m in fresh.iter().rev() {
            let error = m.behebungs_klasse > 0;
            out.push(event(
                if error {
                    AxisEvent::KIND_ERROR
                } else {
                    AxisEvent::KIND_WARNING
                },
                &a.name,
                m.error_id,
                format!(
                    "MC {} {} (remedy class {}, reaction class {})",
                    if error { "error" } else { "warning" },
                    m.error_id,
                    m.behebungs_klasse,
                    m.reaktions_klasse
                ),
                |e| {
                    e.remedy_class = m.behebungs_klasse;
                    e.reaction_class = m.reaktions_klasse;
                },
            ));
        }
        let was = prev.axes.get(k).map_or(0, |b| b.error_code);
        if a.error_code != 0 && a.error_code != was && !fresh.iter().any(|m| m.behebungs_klasse > 0)
        {
            out.push(event(
                AxisEvent::KIND_ERROR,
                &a.name,
                a.error_code,
                format!(
                    "axis error 0x{:X}: {}",
                    a.error_code,
                    AxisEngine::error_text(motion_core::ErrorId(a.error_code))
                ),
                |_| {},
            ));
        }
    }
    let seen = p.clog_warnings;
    let new = n.clog_warnings.saturating_sub(seen);
    let recent = &n.recent_clog_warnings;
    for w in &recent[recent.len().saturating_sub(new)..] {
        out.push(event(
            AxisEvent::KIND_CLOG_WARNING,
            &w.axis,
            w.id.0,
            format!(
                "warning {}: the acknowledgement of order {} lies in the slot (clog, R-HS-5)",
                w.id.0, w.order_id
            ),
            |e| e.order_id = w.order_id,
        ));
    }
    out
}

/// Messages of `next` (newest first) that `prev` did not have: those in front of `prev`'s
/// newest (all of them when `prev` had none).
fn new_messages<'a>(prev: &[McMessage], next: &'a [McMessage]) -> &'a [McMessage] {
    let k = prev
        .first()
        .and_then(|top| next.iter().position(|m| m == top))
        .unwrap_or(next.len());
    &next[..k]
}

fn safety_changes(p: &PlatformStatus, n: &PlatformStatus, out: &mut Vec<AxisEvent>) {
    let mut node = |state: &str, text: String| {
        out.push(event(AxisEvent::KIND_SAFETY, "", 0, text, |e| {
            e.state = state.into()
        }))
    };
    if p.operating_mode != n.operating_mode {
        node(
            "operating_mode",
            format!(
                "operating mode {:?} -> {:?}",
                p.operating_mode, n.operating_mode
            ),
        );
    }
    if p.enabling_switch != n.enabling_switch {
        node(
            "enabling_switch",
            format!("enabling switch {}", on_off(n.enabling_switch)),
        );
    }
    if p.start_button != n.start_button {
        node(
            "start_button",
            format!("START button {}", on_off(n.start_button)),
        );
    }
    for (a, b) in n.axes.iter().zip(&p.axes) {
        let items: [(&str, Flag); 5] = [
            ("feed_hold", |s| s.feed_hold),
            ("velocity_monitoring", |s| s.velocity_monitoring),
            ("torque_limit_monitoring", |s| s.torque_limit_monitoring),
            ("torque_limiting", |s| s.torque_limiting),
            ("referenced", |s| s.referenced),
        ];
        for (item, f) in items {
            if f(a) != f(b) {
                out.push(event(
                    AxisEvent::KIND_SAFETY,
                    &a.name,
                    0,
                    format!("{} {item} {}", a.name, on_off(f(a))),
                    |e| e.state = item.into(),
                ));
            }
        }
    }
}

/// A safety flag of an axis.
type Flag = fn(&AxisSafetyStatus) -> bool;

fn on_off(b: bool) -> &'static str {
    if b {
        "on"
    } else {
        "off"
    }
}

fn event(
    kind: u8,
    object: &str,
    error_id: u32,
    text: String,
    more: impl FnOnce(&mut AxisEvent),
) -> AxisEvent {
    let mut e = AxisEvent {
        kind,
        object: object.into(),
        error_id,
        text,
        ..AxisEvent::default()
    };
    more(&mut e);
    e
}

/// Tracks the orders between their first and final state, for [`Acknowledgements::of`].
#[derive(Default)]
pub struct Acknowledgements {
    /// Open orders: true if admitted buffered (Busy) and not yet Active.
    open: std::collections::HashMap<u64, bool>,
}

impl Acknowledgements {
    /// The acknowledgements of a command state change: ACCEPTED at the first state (a
    /// buffered order later also ACTIVE when it takes over), then DONE, ABORTED or ERROR.
    pub fn of(&mut self, ev: &CommandEvent, label: &CommandLabel) -> Vec<AxisEvent> {
        let id = ev.id.0;
        let mut states: Vec<(&str, u32)> = Vec::new();
        let first = !self.open.contains_key(&id);
        if first {
            states.push(("ACCEPTED", 0));
        }
        match ev.state {
            CommandState::Busy => {
                self.open.insert(id, true);
            }
            CommandState::Active => {
                if self.open.insert(id, false) == Some(true) {
                    states.push(("ACTIVE", 0));
                }
            }
            end => {
                self.open.remove(&id);
                states.push(match end {
                    CommandState::Aborted => ("ABORTED", 0),
                    CommandState::Error(e) => ("ERROR", e.0),
                    _ => ("DONE", 0),
                });
            }
        }
        states
            .into_iter()
            .map(|(state, error_id)| {
                event(
                    AxisEvent::KIND_ACKNOWLEDGEMENT,
                    &label.object,
                    error_id,
                    format!("{} {}: {state}", label.object, label.command),
                    |e| {
                        e.command_id = id;
                        e.state = state.into();
                    },
                )
            })
            .collect()
    }
}

/// Registers `~/events`.
pub fn register(shell: &mut NodeShell<AxisEngine>) -> Result<(), ShellError> {
    let err = |what: &'static str| move |e| ShellError(format!("~/events {what}: {e:?}"));
    let name = private_name(&shell.settings, "events")?;
    let topic = shell
        .node
        .create_topic(&name, AxisEvent::type_name(), &events_qos())
        .map_err(err("topic"))?;
    let publisher = shell
        .node
        .create_publisher::<AxisEvent>(&topic, Some(events_qos()))
        .map_err(err("publisher"))?;
    let mut publisher = motion_runtime::record::RecordedPublisher::new(publisher, name);
    if shell.settings.state_stream {
        // Read off the state stream: every cycle's events are recorded.
        publisher = publisher.lossless();
    }
    let publisher = std::sync::Arc::new(publisher);
    let mut events = Numbered {
        publisher,
        seq: 0,
        orders: Acknowledgements::default(),
    };
    // Lockstep with a state stream: every streamed cycle in order, its orders' acknowledgements
    // before the changes of its state, so a recorded run has the same events every time.
    if shell.settings.state_stream {
        let mut prev: Option<std::sync::Arc<Stamped<AxisSnapshot>>> = None;
        shell.stream_reader(move |item| {
            let mut batch = Vec::new();
            for (timed, label) in &item.events {
                events.acknowledge(&timed.event, label, timed.ros_time_ns, &mut batch);
            }
            // Compared only while someone takes `~/events` (a `--cycles` run that records
            // other topics has no one); the previous snapshot is kept either way.
            if let Some(p) = prev.as_ref().filter(|_| events.publisher.wanted()) {
                let changes = diff(&p.state, &item.state.state);
                events.number(changes, stamp(&item.state), &mut batch);
            }
            prev = Some(item.state.clone());
            events.publish(batch)
        });
        return Ok(());
    }
    // Real time: acknowledgements as they come, state changes between samples at the state rate.
    let mut acks = shell.command_event_tap();
    let handle = shell.handle.clone();
    let period = Duration::from_secs_f64(1.0 / shell.settings.state_rate.max(0.1));
    shell.spawn(async move {
        let mut tick = tokio::time::interval(period);
        tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Skip);
        let mut prev: std::sync::Arc<Stamped<AxisSnapshot>> = handle.snapshot();
        loop {
            let mut batch = Vec::new();
            tokio::select! {
                a = acks.recv() => match a {
                    Some((ev, label, at)) => events.acknowledge(&ev, &label, at, &mut batch),
                    None => break,
                },
                _ = tick.tick() => {
                    let next = handle.snapshot();
                    if next.cycle == prev.cycle {
                        continue;
                    }
                    events.number(diff(&prev.state, &next.state), stamp(&next), &mut batch);
                    prev = next;
                }
            };
            if let Some(work) = events.publish(batch) {
                work.await;
            }
        }
    });
    Ok(())
}

/// The numbering and publishing side of `~/events`: sequence numbers and the orders' state.
struct Numbered {
    publisher: std::sync::Arc<motion_runtime::record::RecordedPublisher<AxisEvent>>,
    seq: u64,
    orders: Acknowledgements,
}

impl Numbered {
    /// The acknowledgements of a command event of the cycle at ROS time `at` [ns], into
    /// `batch`.
    fn acknowledge(
        &mut self,
        ev: &CommandEvent,
        label: &CommandLabel,
        at: i64,
        batch: &mut Vec<AxisEvent>,
    ) {
        let acks = self.orders.of(ev, label);
        self.number(acks, stamp_ns(at), batch);
    }

    /// Stamps `events` with `t` and numbers them into `batch`.
    fn number(&mut self, events: Vec<AxisEvent>, t: Time, batch: &mut Vec<AxisEvent>) {
        for mut e in events {
            e.header = motion_runtime::shell::header(t.clone());
            e.seq = self.seq;
            self.seq += 1;
            batch.push(e);
        }
    }

    /// Records `batch` at once and returns its writing to DDS (none when nothing goes there).
    fn publish(&self, batch: Vec<AxisEvent>) -> Option<motion_runtime::shell::StreamWork> {
        let publisher = self.publisher.clone();
        let dds: Vec<AxisEvent> = batch
            .into_iter()
            .filter_map(|e| {
                let at = motion_runtime::record::time_ns(&e.header.stamp);
                publisher.record(e, at)
            })
            .collect();
        if dds.is_empty() {
            return None;
        }
        Some(Box::pin(async move {
            for e in dds {
                if let Err(e) = publisher.publish_dds(e).await {
                    tracing::warn!("~/events publish failed: {e:?}");
                }
            }
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use axis_engine::platform::raw::RawWarning;
    use axis_engine::platform::OperatingMode;
    use motion_core::{CmdId, ErrorId};

    /// The snapshot of an `isg_mcp` engine with one axis "x" (platform axes present).
    fn snap() -> AxisSnapshot {
        let cfg = axis_engine::EngineConfig {
            platform_profile: axis_engine::PlatformProfile::IsgMcp,
            ..Default::default()
        };
        let e =
            AxisEngine::with_config(vec![("x".into(), axis_engine::AxisConfig::default())], &cfg)
                .unwrap();
        let s = e.snapshot();
        assert_eq!((s.axes.len(), s.platform.axes.len()), (1, 1));
        s
    }

    fn msg(error_id: u32, cycle: u64, remedy: u16) -> McMessage {
        McMessage {
            error_id,
            cycle,
            behebungs_klasse: remedy,
            reaktions_klasse: 2,
        }
    }

    #[test]
    fn new_mc_messages_oldest_first_and_no_repeats() {
        let a = snap();
        let mut b = snap();
        // Newest first in the buffer.
        b.platform.axes[0].messages = vec![msg(91001, 7, 1), msg(12345, 5, 0)];
        b.axes[0].error_code = 91001;
        let ev = diff(&a, &b);
        let ids: Vec<(u8, u32)> = ev.iter().map(|e| (e.kind, e.error_id)).collect();
        // The error code that came with an MC error is not reported twice.
        assert_eq!(
            ids,
            vec![
                (AxisEvent::KIND_WARNING, 12345),
                (AxisEvent::KIND_ERROR, 91001)
            ]
        );
        assert_eq!((ev[1].remedy_class, ev[1].reaction_class), (1, 2));
        assert!(diff(&b, &b).is_empty());
        let mut c = b.clone();
        c.platform.axes[0].messages.insert(0, msg(60241, 9, 1));
        let ev = diff(&b, &c);
        assert_eq!(ev.len(), 1);
        assert_eq!(ev[0].error_id, 60241);
    }

    #[test]
    fn axis_error_without_mc_message_and_safety_changes() {
        let a = snap();
        let mut b = snap();
        b.axes[0].error_code = 0x4260;
        b.platform.operating_mode = OperatingMode::T1;
        b.platform.axes[0].feed_hold = true;
        let ev = diff(&a, &b);
        assert_eq!(ev.len(), 3, "{ev:#?}");
        assert_eq!(
            (ev[0].kind, ev[0].state.as_str()),
            (AxisEvent::KIND_SAFETY, "operating_mode")
        );
        assert_eq!(
            (ev[1].kind, ev[1].object.as_str()),
            (AxisEvent::KIND_SAFETY, "x")
        );
        assert_eq!(ev[1].state, "feed_hold");
        assert_eq!(
            (ev[2].kind, ev[2].error_id),
            (AxisEvent::KIND_ERROR, 0x4260)
        );
    }

    #[test]
    fn clog_warnings_once_each() {
        let a = snap();
        let mut b = snap();
        let w = |o| RawWarning {
            cycle: 3,
            axis: "x".into(),
            id: ErrorId(4906),
            order_id: o,
        };
        b.platform.clog_warnings = 2;
        b.platform.recent_clog_warnings = vec![w(4), w(6)];
        let ev = diff(&a, &b);
        let orders: Vec<u32> = ev.iter().map(|e| e.order_id).collect();
        assert_eq!(orders, vec![4, 6]);
        let mut c = b.clone();
        c.platform.clog_warnings = 3;
        c.platform.recent_clog_warnings.push(w(9));
        let ev = diff(&b, &c);
        assert_eq!(ev.len(), 1);
        assert_eq!(
            (ev[0].kind, ev[0].order_id),
            (AxisEvent::KIND_CLOG_WARNING, 9)
        );
    }

    #[test]
    fn acknowledgements_of_an_order() {
        let mut acks = Acknowledgements::default();
        let label = CommandLabel {
            object: "x".into(),
            command: "move_absolute".into(),
        };
        let ev = |state| CommandEvent {
            id: CmdId(5),
            state,
        };
        let states = |v: Vec<AxisEvent>| v.into_iter().map(|e| e.state).collect::<Vec<_>>();
        assert_eq!(
            states(acks.of(&ev(CommandState::Busy), &label)),
            ["ACCEPTED"]
        );
        assert_eq!(
            states(acks.of(&ev(CommandState::Active), &label)),
            ["ACTIVE"]
        );
        assert_eq!(states(acks.of(&ev(CommandState::Done), &label)), ["DONE"]);
        // Immediately active, then an error.
        assert_eq!(
            states(acks.of(&ev(CommandState::Active), &label)),
            ["ACCEPTED"]
        );
        let e = acks.of(&ev(CommandState::Error(ErrorId(0x4B04))), &label);
        assert_eq!((e[0].state.as_str(), e[0].error_id), ("ERROR", 0x4B04));
        assert!(acks.open.is_empty());
    }
}
