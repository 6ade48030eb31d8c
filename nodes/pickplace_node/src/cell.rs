//! The engine as the cycle runs it: [`PickPlaceEngine`] plus what only the shell needs
//! (pick_and_place.md §18): partial parameter writes merged onto the current `scPar` inside the
//! cycle (so two writes never race), parameter reads, the action's "write the profile, then
//! raise the edge" in one cycle (waiting while `xProfileInPreparation` is TRUE, §18), which
//! replies carry a command lifetime (execute, homing), and the cell events of every cycle
//! forwarded to `~/events` as they happen.

use motion_core::{CmdId, CommandEvent, CommandState, Engine, ErrorId, Rejection, Tick};
use pickplace_engine::config::MAX_BELTS;
use pickplace_engine::{
    error_ids as ids, CellEvent, ConveyorBeltPar, PickPlaceCommand, PickPlaceEngine,
    PickPlaceSnapshot, ScPar,
};
use serde_yaml::{Mapping, Value};
use std::collections::{HashMap, VecDeque};
use tokio::sync::mpsc::UnboundedSender;

/// Points of the TCP path line strip in [`CellSnapshot::path`].
pub const PATH_SAMPLES: usize = 64;

/// A command of the node: an engine command or a shell-level parameter operation.
#[derive(Clone, Debug)]
pub enum CellCommand {
    /// Passed to the engine unchanged.
    Engine(PickPlaceCommand),
    /// Partial `scPar` write: the given fields over the current values (§3.4).
    MergeParams(Mapping),
    /// Partial `ascConveyorBeltPar[belt]` write (§3.5).
    MergeBeltParams {
        /// Belt 1 … 16.
        belt: u8,
        /// Fields to change.
        params: Mapping,
    },
    /// Reads `scPar` (belt 0) or `ascConveyorBeltPar[belt]` as YAML.
    GetParams {
        /// 0 or 1 … 16.
        belt: u8,
    },
    /// `~/pick_and_place`: optional `scPar` changes, then the execute edge, in one cycle.
    ExecuteWith {
        /// `eSetTarget` 0 … 5.
        set_target: u8,
        /// New `lr…TargetPos` (X … C, Aux1).
        target_pose: Option<[f64; 7]>,
        /// Further `scPar` fields.
        params: Option<Mapping>,
    },
}

/// A command read from a launch config's `script` is an engine command, as the engine spells
/// it (`{DetectWorkpiece: {...}}`); the shell-level operations come only from services.
impl<'de> serde::Deserialize<'de> for CellCommand {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        PickPlaceCommand::deserialize(d).map(CellCommand::Engine)
    }
}

/// What an accepted command answers.
#[derive(Clone, Debug, PartialEq)]
pub struct CellReply {
    /// The engine's id of the input change.
    pub id: CmdId,
    /// The command has a lifetime reported by command events (execute, homing).
    pub tracked: bool,
    /// YAML text of a parameter read.
    pub text: Option<String>,
}

/// The snapshot published on the state topics.
#[derive(Clone, Debug)]
pub struct CellSnapshot {
    /// The engine's snapshot.
    pub cell: PickPlaceSnapshot,
    /// TCP path of the running leg (MCS, mm), empty when no path runs.
    pub path: Vec<[f64; 3]>,
    /// `ascConveyorBeltPar[1..16]` (belt frames and working areas for `~/markers`).
    pub belt_params: [ConveyorBeltPar; MAX_BELTS],
}

/// Cell events of one cycle with the simulated time at the end of that cycle [s].
pub type EventBatch = (f64, Vec<CellEvent>);

/// Ids of goals whose edge waits for `xProfileInPreparation = FALSE` carry this bit (the
/// engine counts its ids from 1 and never reaches it).
pub const WAITING_ID_BIT: u64 = 1 << 63;

/// A `~/pick_and_place` goal waiting for its edge.
#[derive(Clone, Debug)]
struct Waiting {
    id: CmdId,
    set_target: u8,
    /// The goal's `scPar` (validated at acceptance), written in the cycle of its edge.
    params: Option<Box<ScPar>>,
}

/// The engine with the shell's additions.
pub struct Cell {
    engine: PickPlaceEngine,
    events: Option<UnboundedSender<EventBatch>>,
    waiting: VecDeque<Waiting>,
    next_waiting: u64,
    /// Engine id of a waiting goal's edge -> the goal's id, until its final event.
    raised: HashMap<CmdId, CmdId>,
    /// Final events of waiting goals that were cancelled, reported in the next cycle.
    cancelled: Vec<CommandEvent>,
}

impl Cell {
    /// `scPar` (belt 0) or `ascConveyorBeltPar[belt]` as YAML: a pure read, served to
    /// `~/get_params` through the controller's query path (no command, no cycle needed).
    pub fn params_yaml(&self, belt: u8) -> Result<String, Rejection> {
        if belt == 0 {
            serde_yaml::to_string(self.engine.params())
        } else {
            let p = self
                .engine
                .belt_params(belt)
                .ok_or_else(|| Rejection::unknown_object("belt", &belt.to_string()))?;
            serde_yaml::to_string(&p)
        }
        .map_err(|e| Rejection::new(ids::INVALID_PARAMETER, e.to_string()))
    }

    /// Wraps `engine`; cell events go to `events` (dropped when `None`).
    pub fn new(engine: PickPlaceEngine, events: Option<UnboundedSender<EventBatch>>) -> Self {
        Cell {
            engine,
            events,
            waiting: VecDeque::new(),
            next_waiting: 0,
            raised: HashMap::new(),
            cancelled: Vec::new(),
        }
    }

    /// Raises the edge of the oldest waiting goal once no profile is in preparation (one edge
    /// per cycle: the engine takes it in this cycle's step).
    fn raise_waiting(&mut self, events: &mut Vec<CommandEvent>) {
        if self.waiting.is_empty() || self.engine.profile_in_preparation() {
            return;
        }
        let Some(w) = self.waiting.pop_front() else {
            return;
        };
        if let Some(p) = w.params {
            if let Err(r) = self.engine.command(PickPlaceCommand::SetParams(p)) {
                let state = CommandState::Error(r.error_id);
                events.push(CommandEvent { id: w.id, state });
                return;
            }
        }
        match self.engine.command(PickPlaceCommand::Execute {
            set_target: w.set_target,
        }) {
            Ok(eid) => {
                self.raised.insert(eid, w.id);
            }
            Err(r) => events.push(CommandEvent {
                id: w.id,
                state: CommandState::Error(r.error_id),
            }),
        }
    }

    /// The wrapped engine.
    pub fn engine(&self) -> &PickPlaceEngine {
        &self.engine
    }

    fn merged_params(&self, patch: &Mapping) -> Result<ScPar, Rejection> {
        merge(self.engine.params(), patch, "scPar")
    }
}

/// `current` with the fields of `patch` replaced. Unknown fields are `UNKNOWN_OBJECT`, values
/// of the wrong type `InvalidParameter` (90001); ranges are checked by the engine's write.
pub fn merge<T>(current: &T, patch: &Mapping, what: &str) -> Result<T, Rejection>
where
    T: serde::Serialize + serde::de::DeserializeOwned,
{
    let mut value = serde_yaml::to_value(current)
        .map_err(|e| Rejection::new(ids::INVALID_PARAMETER, format!("{what}: {e}")))?;
    let Value::Mapping(fields) = &mut value else {
        return Err(Rejection::new(
            ids::INVALID_PARAMETER,
            format!("{what} is not a structure"),
        ));
    };
    for (k, v) in patch {
        let name = k.as_str().unwrap_or("?");
        match fields.get_mut(k) {
            Some(slot) => *slot = v.clone(),
            None => {
                return Err(Rejection::new(
                    ErrorId::UNKNOWN_OBJECT,
                    format!(
                        "{what} has no field '{name}' (fields: {})",
                        field_names(fields)
                    ),
                ))
            }
        }
    }
    serde_yaml::from_value(value.clone()).map_err(|e| {
        // Name the field whose value does not fit (serde's message names only the type).
        let base = serde_yaml::to_value(current).ok();
        let bad = patch.iter().find(|(k, v)| {
            let Some(Value::Mapping(mut one)) = base.clone() else {
                return false;
            };
            one.insert((*k).clone(), (*v).clone());
            serde_yaml::from_value::<T>(Value::Mapping(one)).is_err()
        });
        let field = bad.and_then(|(k, _)| k.as_str()).unwrap_or("?");
        Rejection::new(ids::INVALID_PARAMETER, format!("{what}.{field}: {e}"))
    })
}

fn field_names(m: &Mapping) -> String {
    m.keys()
        .filter_map(|k| k.as_str())
        .collect::<Vec<_>>()
        .join(", ")
}

/// Parses a partial parameter text (YAML or JSON mapping; empty = no change).
pub fn parse_patch(text: &str, what: &str) -> Result<Option<Mapping>, Rejection> {
    if text.trim().is_empty() {
        return Ok(None);
    }
    match serde_yaml::from_str::<Value>(text) {
        Ok(Value::Mapping(m)) => Ok(Some(m)),
        Ok(Value::Null) => Ok(None),
        Ok(other) => Err(Rejection::new(
            ids::INVALID_PARAMETER,
            format!(
                "{what}: expected a mapping of fields, got {}",
                serde_yaml::to_string(&other).unwrap_or_default().trim()
            ),
        )),
        Err(e) => Err(Rejection::new(
            ids::INVALID_PARAMETER,
            format!("{what}: not YAML: {e}"),
        )),
    }
}

fn reply(id: CmdId, tracked: bool) -> CellReply {
    CellReply {
        id,
        tracked,
        text: None,
    }
}

impl Engine for Cell {
    type Command = CellCommand;
    type Reply = CellReply;
    type Snapshot = CellSnapshot;

    fn fail_safe_stop(&mut self) {
        self.engine.fail_safe_stop();
    }

    fn at_rest(&self) -> bool {
        self.engine.at_rest()
    }

    fn command(&mut self, cmd: CellCommand) -> Result<CellReply, Rejection> {
        match cmd {
            CellCommand::Engine(c) => {
                let edge = |c: &PickPlaceCommand| {
                    matches!(
                        c,
                        PickPlaceCommand::Execute { .. } | PickPlaceCommand::GroupHome
                    )
                };
                let tracked = match &c {
                    PickPlaceCommand::Hmi(inner) => edge(inner),
                    other => edge(other),
                };
                self.engine.command(c).map(|id| reply(id, tracked))
            }
            CellCommand::MergeParams(patch) => {
                let p = self.merged_params(&patch)?;
                self.engine
                    .command(PickPlaceCommand::SetParams(Box::new(p)))
                    .map(|id| reply(id, false))
            }
            CellCommand::MergeBeltParams { belt, params } => {
                let current = self
                    .engine
                    .belt_params(belt)
                    .ok_or_else(|| Rejection::unknown_object("belt", &belt.to_string()))?;
                let p: ConveyorBeltPar =
                    merge(&current, &params, &format!("ascConveyorBeltPar[{belt}]"))?;
                self.engine
                    .command(PickPlaceCommand::SetBeltParams { belt, params: p })
                    .map(|id| reply(id, false))
            }
            CellCommand::GetParams { belt } => Ok(CellReply {
                id: CmdId(0),
                tracked: false,
                text: Some(self.params_yaml(belt)?),
            }),
            CellCommand::ExecuteWith {
                set_target,
                target_pose,
                params,
            } => {
                let mut profile = None;
                if target_pose.is_some() || params.is_some() {
                    let mut p = match &params {
                        Some(m) => self.merged_params(m)?,
                        None => self.engine.params().clone(),
                    };
                    if let Some(t) = target_pose {
                        p.target_pos = t;
                    }
                    p.validate()?;
                    if p != *self.engine.params() {
                        profile = Some(Box::new(p));
                    }
                }
                if self.waiting.is_empty() && !self.engine.profile_in_preparation() {
                    if let Some(p) = profile {
                        self.engine.command(PickPlaceCommand::SetParams(p))?;
                    }
                    return self
                        .engine
                        .command(PickPlaceCommand::Execute { set_target })
                        .map(|id| reply(id, true));
                }
                // §18: the action raises its edge once xProfileInPreparation is FALSE.
                self.next_waiting += 1;
                let id = CmdId(WAITING_ID_BIT | self.next_waiting);
                self.waiting.push_back(Waiting {
                    id,
                    set_target,
                    params: profile,
                });
                Ok(reply(id, true))
            }
        }
    }

    fn step(&mut self, tick: Tick, events: &mut Vec<CommandEvent>) {
        events.append(&mut self.cancelled);
        self.raise_waiting(events);
        let from = events.len();
        self.engine.step(tick, events);
        if !self.raised.is_empty() {
            for ev in &mut events[from..] {
                if let Some(&goal) = self.raised.get(&ev.id) {
                    if ev.state.is_final() {
                        self.raised.remove(&ev.id);
                    }
                    ev.id = goal;
                }
            }
        }
        let cell_events = self.engine.drain_events();
        if !cell_events.is_empty() {
            if let Some(tx) = &self.events {
                let _ = tx.send(((tick.index + 1) as f64 * tick.dt, cell_events));
            }
        }
    }

    fn snapshot(&self) -> CellSnapshot {
        let mut belt_params = [ConveyorBeltPar::default(); MAX_BELTS];
        for (i, p) in belt_params.iter_mut().enumerate() {
            *p = self.engine.belt_params(i as u8 + 1).unwrap_or_default();
        }
        CellSnapshot {
            cell: self.engine.snapshot(),
            path: self.engine.active_path(PATH_SAMPLES),
            belt_params,
        }
    }

    fn cancel(&mut self, id: CmdId) -> Result<(), Rejection> {
        if let Some(i) = self.waiting.iter().position(|w| w.id == id) {
            // Its edge was never raised: nothing to halt.
            self.waiting.remove(i);
            let state = CommandState::Aborted;
            self.cancelled.push(CommandEvent { id, state });
            return Ok(());
        }
        match self.raised.iter().find(|(_, goal)| **goal == id) {
            Some((&eid, _)) => self.engine.cancel(eid),
            None => self.engine.cancel(id),
        }
    }

    fn reply_id(reply: &CellReply) -> Option<CmdId> {
        reply.tracked.then_some(reply.id)
    }

    fn error_text(id: ErrorId) -> String {
        match error_name(id) {
            Some(name) => format!("{name} ({})", id.0),
            None => format!("error {}", id.0),
        }
    }
}

/// The manual's name of an error or warning id (pick_and_place.md §16).
pub fn error_name(id: ErrorId) -> Option<&'static str> {
    Some(match id {
        ids::MAX_WORKPIECES => "MaxWorkpiecesReached",
        ids::SW_LIMIT_POS => "SWLimitPos",
        ids::SW_LIMIT_NEG => "SWLimitNeg",
        ids::HW_LIMIT_POS => "HwLimitPos",
        ids::HW_LIMIT_NEG => "HwLimitNeg",
        ids::INVALID_PARAMETER => "InvalidParameter",
        ids::INVALID_PATH_MODE => "InvalidPathMode",
        ids::INVALID_TRACKING_MODE => "InvalidTrackingMode",
        ids::COORD_SYSTEM_NOT_SUPPORTED => "CoordSystemNotSupported",
        ids::BELT_NOT_CONFIGURED => "BeltNotConfigured",
        ids::ELLIPSE_FALLBACK_LINEAR => "EllipseFallbackLinear",
        ids::PROFILE_BUFFER_FULL => "ProfileBufferFull",
        ids::AXES_NOT_ENABLED => "AxesNotEnabled",
        ids::COMMAND_NOT_ALLOWED => "CommandNotAllowed",
        ids::FOLLOWING_ERROR => "FollowingError",
        ids::STOP_ALL_DURING_SYNC => "StopAllDuringSync",
        ids::SYNC_LIMIT_EXCEEDED => "SyncLimitExceeded",
        ids::HOMING_FAILED => "HomingFailed",
        ids::OVERRIDE_OUT_OF_RANGE => "OverrideOutOfRange",
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use pickplace_engine::PickPlaceConfig;

    fn cell() -> Cell {
        Cell::new(
            PickPlaceEngine::new(PickPlaceConfig::default()).unwrap(),
            None,
        )
    }

    fn patch(text: &str) -> Mapping {
        parse_patch(text, "params").unwrap().unwrap()
    }

    #[test]
    fn partial_write_keeps_the_other_fields() {
        let mut c = cell();
        let before = c.engine().params().clone();
        c.command(CellCommand::MergeParams(patch(
            "{path_vel: 250, target_pos: [1, 2, 3, 180, 0, 0, 0]}",
        )))
        .unwrap();
        let after = c.engine().params();
        assert_eq!(after.path_vel, 250.0);
        assert_eq!(after.target_pos, [1.0, 2.0, 3.0, 180.0, 0.0, 0.0, 0.0]);
        assert_eq!(after.path_acc, before.path_acc);
        assert_eq!(after.stop_dec, before.stop_dec);
    }

    #[test]
    fn bad_writes_are_rejected_and_change_nothing() {
        let mut c = cell();
        let before = c.engine().params().clone();
        let cases = [
            ("{path_vel: -5}", ids::INVALID_PARAMETER, "lrPathVel"),
            ("{path_vel: .nan}", ids::INVALID_PARAMETER, "NaN"),
            ("{path_mode: 7}", ids::INVALID_PATH_MODE, "7"),
            (
                "{no_such_field: 1}",
                ErrorId::UNKNOWN_OBJECT,
                "no_such_field",
            ),
            ("{path_vel: fast}", ids::INVALID_PARAMETER, "path_vel"),
            ("{target_pos: [1, 2]}", ids::INVALID_PARAMETER, "target_pos"),
        ];
        for (text, id, needle) in cases {
            let r = c
                .command(CellCommand::MergeParams(patch(text)))
                .unwrap_err();
            assert_eq!(r.error_id, id, "{text}: {}", r.message);
            assert!(r.message.contains(needle), "{text}: {}", r.message);
            assert_eq!(c.engine().params(), &before, "{text}");
        }
        assert!(parse_patch("[1, 2]", "params").is_err());
        assert_eq!(parse_patch("  ", "params").unwrap(), None);
    }

    #[test]
    fn belt_params_merge_and_unknown_belt() {
        let mut c = cell();
        c.command(CellCommand::MergeBeltParams {
            belt: 2,
            params: patch("{lower_sync_limit: 10, upper_sync_limit: 500}"),
        })
        .unwrap();
        let p = c.engine().belt_params(2).unwrap();
        assert_eq!(
            (p.lower_sync_limit, p.upper_sync_limit, p.z_dist_belt),
            (10.0, 500.0, 0.0)
        );
        let r = c
            .command(CellCommand::MergeBeltParams {
                belt: 17,
                params: patch("{z_dist_belt: 1}"),
            })
            .unwrap_err();
        assert_eq!(r.error_id, ErrorId::UNKNOWN_OBJECT);
        let r = c.command(CellCommand::GetParams { belt: 0 }).unwrap();
        assert!(r.text.unwrap().contains("path_vel:"));
        let r = c.command(CellCommand::GetParams { belt: 2 }).unwrap();
        assert!(r.text.unwrap().contains("upper_sync_limit: 500"));
    }

    #[test]
    fn execute_with_a_rejected_profile_raises_no_edge() {
        let mut c = cell();
        let r = c
            .command(CellCommand::ExecuteWith {
                set_target: 0,
                target_pose: Some([f64::NAN; 7]),
                params: None,
            })
            .unwrap_err();
        assert_eq!(r.error_id, ids::INVALID_PARAMETER, "{}", r.message);
        let ok = c
            .command(CellCommand::ExecuteWith {
                set_target: 0,
                target_pose: Some([5.0, 0.0, 0.0, 180.0, 0.0, 0.0, 0.0]),
                params: None,
            })
            .unwrap();
        assert!(ok.tracked);
        assert_eq!(c.engine().params().target_pos[0], 5.0);
        assert_eq!(Cell::reply_id(&ok), Some(ok.id));
        let level = c
            .command(CellCommand::Engine(PickPlaceCommand::SetEnable(true)))
            .unwrap();
        assert_eq!(Cell::reply_id(&level), None);
    }

    /// §18: a goal arriving while a profile is prepared waits for its edge instead of being
    /// refused with ProfileBufferFull; its events carry the goal's id; a waiting goal cancels
    /// without an edge.
    #[test]
    fn goals_wait_for_the_preparation() {
        let mut cfg = PickPlaceConfig::default();
        cfg.params.max_vel = [0.0; 7];
        cfg.params.max_acc_dec = [0.0; 7];
        cfg.params.max_jerk = [0.0; 7];
        cfg.params.path_vel = 100.0;
        cfg.params.path_acc = 1000.0;
        cfg.params.path_dec = 1000.0;
        cfg.initial_tcp = Some([0.0, 0.0, 0.0, 180.0, 0.0, 0.0, 0.0]);
        cfg.path_prep_cycles = 5;
        let mut c = Cell::new(PickPlaceEngine::new(cfg).unwrap(), None);
        c.command(CellCommand::Engine(PickPlaceCommand::SetEnable(true)))
            .unwrap();
        c.command(CellCommand::Engine(PickPlaceCommand::SetRegulatorOn(true)))
            .unwrap();
        let mut ev = Vec::new();
        let mut index = 0;
        let mut run = |c: &mut Cell, n: u64, ev: &mut Vec<CommandEvent>| {
            for _ in 0..n {
                c.step(Tick { index, dt: 0.001 }, ev);
                index += 1;
            }
        };
        run(&mut c, 2, &mut ev);
        let goal = |x: f64| CellCommand::ExecuteWith {
            set_target: 0,
            target_pose: Some([x, 0.0, 0.0, 180.0, 0.0, 0.0, 0.0]),
            params: None,
        };
        let a = c.command(goal(10.0)).unwrap();
        run(&mut c, 1, &mut ev);
        assert!(c.engine().profile_in_preparation());
        let b = c.command(goal(20.0)).unwrap();
        let d = c.command(goal(30.0)).unwrap();
        assert!(b.id.0 & WAITING_ID_BIT != 0 && b.tracked);
        assert_eq!(
            c.engine().params().target_pos[0],
            10.0,
            "a waiting goal's profile is not written yet"
        );
        c.cancel(d.id).unwrap();
        run(&mut c, 3000, &mut ev);
        let final_of = |id: CmdId| ev.iter().rev().find(|e| e.id == id).map(|e| e.state);
        assert_eq!(final_of(a.id), Some(CommandState::Done));
        assert_eq!(final_of(b.id), Some(CommandState::Done), "{ev:?}");
        assert_eq!(final_of(d.id), Some(CommandState::Aborted));
        assert!(
            !ev.iter().any(|e| matches!(e.state, CommandState::Error(_))),
            "{ev:?}"
        );
        assert_eq!(c.snapshot().cell.tcp[0], 20.0);
    }

    /// A resume edge (§9.2) while the held profile still has its own id: both ids end with
    /// the profile (else a resuming `~/pick_and_place` goal would never end), and cancelling
    /// the resume id halts the held profile.
    #[test]
    fn a_resume_edge_ends_with_the_held_profile() {
        use pickplace_engine::StopInputs;
        let mut cfg = PickPlaceConfig::default();
        cfg.params.max_vel = [0.0; 7];
        cfg.params.max_acc_dec = [0.0; 7];
        cfg.params.max_jerk = [0.0; 7];
        cfg.params.path_vel = 100.0;
        cfg.params.path_acc = 1000.0;
        cfg.params.path_dec = 1000.0;
        cfg.params.target_pos = [300.0, 0.0, 0.0, 180.0, 0.0, 0.0, 0.0];
        cfg.initial_tcp = Some([0.0, 0.0, 0.0, 180.0, 0.0, 0.0, 0.0]);
        let mut c = Cell::new(PickPlaceEngine::new(cfg).unwrap(), None);
        let mut ev = Vec::new();
        let mut index = 0;
        let mut run = |c: &mut Cell, n: u64, ev: &mut Vec<CommandEvent>| {
            for _ in 0..n {
                c.step(Tick { index, dt: 0.001 }, ev);
                index += 1;
            }
        };
        let cmd = |c: &mut Cell, x: PickPlaceCommand| c.command(CellCommand::Engine(x)).unwrap();
        let halt = |v: bool| {
            PickPlaceCommand::SetStopInputs(StopInputs {
                path_halt: Some(v),
                ..Default::default()
            })
        };
        let final_of =
            |ev: &[CommandEvent], id: CmdId| ev.iter().rev().find(|e| e.id == id).map(|e| e.state);
        cmd(&mut c, PickPlaceCommand::SetEnable(true));
        cmd(&mut c, PickPlaceCommand::SetRegulatorOn(true));
        run(&mut c, 2, &mut ev);
        for cancel_resume in [false, true] {
            let start = c.snapshot().cell.tcp[0];
            let target = if start < 150.0 { 300.0 } else { 0.0 };
            let a = c
                .command(CellCommand::ExecuteWith {
                    set_target: 0,
                    target_pose: Some([target, 0.0, 0.0, 180.0, 0.0, 0.0, 0.0]),
                    params: None,
                })
                .unwrap();
            run(&mut c, 1000, &mut ev);
            cmd(&mut c, halt(true));
            run(&mut c, 500, &mut ev);
            cmd(&mut c, halt(false));
            run(&mut c, 10, &mut ev);
            assert!(c.snapshot().cell.outputs.path_hold);
            let b = cmd(&mut c, PickPlaceCommand::Execute { set_target: 0 });
            if cancel_resume {
                run(&mut c, 200, &mut ev);
                c.cancel(b.id).unwrap();
            }
            run(&mut c, 5000, &mut ev);
            let end = if cancel_resume {
                CommandState::Aborted
            } else {
                CommandState::Done
            };
            assert_eq!(final_of(&ev, a.id), Some(end), "{ev:?}");
            assert_eq!(final_of(&ev, b.id), Some(end), "{ev:?}");
            let tcp = c.snapshot().cell.tcp[0];
            assert_eq!(tcp == target, !cancel_resume, "{tcp}");
        }
    }

    #[test]
    fn events_are_forwarded_per_cycle() {
        let (tx, mut rx) = tokio::sync::mpsc::unbounded_channel();
        let mut c = Cell::new(
            PickPlaceEngine::new(PickPlaceConfig::default()).unwrap(),
            Some(tx),
        );
        c.command(CellCommand::Engine(PickPlaceCommand::SetEnable(true)))
            .unwrap();
        let mut ev = Vec::new();
        c.step(
            Tick {
                index: 4,
                dt: 0.001,
            },
            &mut ev,
        );
        let (t, batch) = rx.try_recv().expect("a batch");
        assert!((t - 0.005).abs() < 1e-12);
        assert!(batch.iter().any(|e| matches!(
            e,
            CellEvent::StateChanged {
                to: pickplace_engine::TmState::Ready,
                ..
            }
        )));
        c.step(
            Tick {
                index: 5,
                dt: 0.001,
            },
            &mut ev,
        );
        assert!(rx.try_recv().is_err(), "no events, no batch");
    }
}
