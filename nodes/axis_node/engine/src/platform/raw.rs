//! Raw FB layer (plcopen_platform.md §12.2, §4, §6.3): exact PLC emulation for tests.
//!
//! [`AxisEngine::fb_cycle`] runs one PLC cycle: the listed FB instances are called in the
//! given order with their inputs (instances not listed are not called), then the MC runs one
//! cycle. Each instance has the FB_IDLE / FB_ACTIVE / FB_ERROR states of R-FB-1, keeps its
//! order number (§4.3; a re-trigger while ACTIVE reuses it, R-FB-3) and takes only the
//! acknowledgements of its own orders from its axis' single acknowledgement queue (R-HS-5):
//! an acknowledgement nobody consumes blocks all later ones of that axis ("clogging"); after
//! more than 2 cycles at the head, warning 4906 is recorded. Done/CommandAborted/Error are
//! latched until Execute falls (R-HS-2).
//!
//! Part 4 group FBs (`AxisCommand::Group`) work the same way on their group's channel: one
//! acknowledgement queue per group (after the axes' queues), the channel's order slot of
//! R-HS-3/R-HS-4, order numbers, clogging with the group's name in the warning.

use super::ids::*;
use crate::command::{AxisCommand, AxisReply};
use crate::engine::AxisEngine;
use motion_core::{CommandEvent, CommandState, Engine, ErrorId, Tick};
use std::collections::VecDeque;

use super::raw_state::{Ack, Inst};
pub use super::raw_state::{AckKind, FbCall, FbOut, FbState, RawWarning};

impl AxisEngine {
    /// One PLC cycle of the raw FB layer (§12.2): calls in order, then one MC cycle. Events of
    /// commands not owned by raw instances are appended to `events`.
    pub fn fb_cycle(
        &mut self,
        tick: Tick,
        calls: &[FbCall],
        events: &mut Vec<CommandEvent>,
    ) -> Vec<FbOut> {
        // Acknowledgement queues: the axes, then the groups' channels.
        let n_slots = self.set.axes.len() + self.groups.list.len();
        if self.raw.acks.len() != n_slots {
            self.raw.acks = vec![VecDeque::new(); n_slots];
            self.raw.clog_warned = vec![None; n_slots];
        }
        let mut outs = Vec::with_capacity(calls.len());
        for call in calls {
            outs.push(self.raw_call(call));
        }
        // (3) the MC consumes the orders: aborts caused by them first, then ACCEPTED, then
        // what the cycle itself produces (`step` routes raw-owned events to their queues).
        let from = events.len();
        events.append(&mut self.set.fbs.events);
        let mut accepted = std::mem::take(&mut self.raw.accepted);
        // An order overwritten in its own cycle (MC_Stop / MC_GroupStop, R-HS-4) is
        // acknowledged ACCEPTED before its ABORTED.
        for e in &events[from..] {
            let owner = self.raw.owner_of.get(&e.id).copied();
            if let Some(p) = owner
                .filter(|_| e.state.is_final())
                .and_then(|i| accepted.iter().position(|a| a.0 == i))
            {
                let a = accepted.remove(p);
                self.raw_accepted(a);
            }
        }
        self.raw_route(events, from);
        for a in accepted {
            self.raw_accepted(a);
        }
        Engine::step(self, tick, events);
        // InVelocity acknowledgements.
        for k in 0..self.raw.instances.len() {
            let i = &self.raw.instances[k];
            if i.state != FbState::Active || i.in_velocity_acked {
                continue;
            }
            let iv = i
                .engine
                .last()
                .and_then(|&id| self.set.fbs.outputs_with(id, false))
                .is_some_and(|o| o.in_velocity);
            if iv {
                let (axis, order_id) = (i.axis, i.order_id);
                self.raw.instances[k].in_velocity_acked = true;
                self.raw.acks[axis].push_back(Ack {
                    owner: k,
                    kind: AckKind::InVelocity,
                    posted: self.raw.cycle,
                    order_id,
                });
            }
        }
        // Clog watchdog: the same acknowledgement at the head for more than 2 cycles.
        for ax in 0..n_slots {
            if let Some(h) = self.raw.acks[ax].front().copied() {
                let key = Some((h.owner, h.order_id));
                if self.raw.cycle > h.posted + 2 && self.raw.clog_warned[ax] != key {
                    self.raw.clog_warned[ax] = key;
                    self.raw.warnings.push(RawWarning {
                        cycle: self.raw.cycle,
                        axis: self.raw_slot_name(ax),
                        id: ERR_SIM_HLI_ACK_CLOG,
                        order_id: h.order_id,
                    });
                }
            }
        }
        self.raw.cycle += 1;
        outs
    }

    /// Posts the ACCEPTED acknowledgement of an order placed in this cycle.
    fn raw_accepted(&mut self, (inst, axis, order_id): (usize, usize, u32)) {
        self.raw.acks[axis].push_back(Ack {
            owner: inst,
            kind: AckKind::Accepted,
            posted: self.raw.cycle,
            order_id,
        });
    }

    /// Warnings of the raw layer so far (4906).
    pub fn raw_warnings(&self) -> &[RawWarning] {
        &self.raw.warnings
    }

    /// After a step (with or without [`AxisEngine::fb_cycle`], e.g. cycles a free-running
    /// node runs between `~/fb/cycle` requests): the events of raw-owned commands from
    /// `events[from..]` become acknowledgements in their queues. No allocation.
    pub(crate) fn raw_route(&mut self, events: &mut Vec<CommandEvent>, from: usize) {
        if self.raw.owner_of.is_empty() {
            return;
        }
        let mut k = from;
        while k < events.len() {
            if self.raw_ack(events[k]) {
                events.remove(k);
            } else {
                k += 1;
            }
        }
    }

    /// Queues the acknowledgement of a raw-owned command's final event; false if the command
    /// is not raw-owned (the event stays with the caller).
    fn raw_ack(&mut self, e: CommandEvent) -> bool {
        let Some(&k) = self.raw.owner_of.get(&e.id) else {
            return false;
        };
        let kind = match e.state {
            CommandState::Done => AckKind::Done,
            CommandState::Aborted => AckKind::Aborted,
            CommandState::Error(id) => AckKind::Error(self.platform.error_id(&self.set, e.id, id)),
            // The admission is acknowledged as ACCEPTED by the raw layer itself; the axis
            // engine never ends an instance without an output (Ended).
            CommandState::Busy | CommandState::Active | CommandState::Ended => return true,
        };
        let i = &self.raw.instances[k];
        let (axis, order_id) = (i.axis, i.order_id);
        self.raw.acks[axis].push_back(Ack {
            owner: k,
            kind,
            posted: self.raw.cycle,
            order_id,
        });
        true
    }

    fn raw_call(&mut self, call: &FbCall) -> FbOut {
        let k = match self.raw.by_name.get(&call.instance) {
            Some(&k) => k,
            None => {
                let k = self.raw.instances.len();
                self.raw.instances.push(Inst {
                    name: call.instance.clone(),
                    ..Inst::default()
                });
                self.raw.by_name.insert(call.instance.clone(), k);
                k
            }
        };
        let axis = self.raw_slot(&call.fb);
        // Consume this instance's acknowledgements at the head of its axis' queue.
        let qa = self.raw.instances[k].axis;
        if self.raw.instances[k].state == FbState::Active {
            while let Some(h) = self.raw.acks[qa].front().copied() {
                if h.owner != k {
                    break;
                }
                self.raw.acks[qa].pop_front();
                if self.raw.clog_warned[qa].is_some_and(|w| w.0 == k) {
                    self.raw.clog_warned[qa] = None;
                }
                let i = &mut self.raw.instances[k];
                match h.kind {
                    AckKind::Accepted => {
                        i.out.busy = true;
                        i.out.active = true;
                    }
                    AckKind::InVelocity => i.out.in_velocity = true,
                    AckKind::Done => {
                        i.in_flight = i.in_flight.saturating_sub(1);
                        if i.in_flight == 0 {
                            i.out.done = true;
                            i.out.busy = false;
                            i.out.active = false;
                            i.state = FbState::Idle;
                        }
                    }
                    AckKind::Aborted => {
                        i.in_flight = i.in_flight.saturating_sub(1);
                        if i.in_flight == 0 {
                            i.out.command_aborted = true;
                            i.out.busy = false;
                            i.out.active = false;
                            i.state = FbState::Idle;
                        }
                    }
                    AckKind::Error(e) => {
                        i.in_flight = 0;
                        i.out.error = true;
                        i.out.error_id = e;
                        i.out.busy = false;
                        i.out.active = false;
                        i.state = FbState::Idle;
                    }
                }
            }
        }
        let i = &mut self.raw.instances[k];
        let rising = call.execute && !i.prev_execute;
        let falling = !call.execute && i.prev_execute;
        i.prev_execute = call.execute;
        if falling {
            // R-HS-2: final results are cleared only by the falling edge.
            i.out.done = false;
            i.out.command_aborted = false;
            i.out.error = false;
            i.out.error_id = ErrorId::NONE;
            // The MC sees the level too (MC_Stop / MC_GroupStop release the axis or group).
            if let Some(id) = i.engine.last().copied() {
                let _ = self.dispatch(AxisCommand::SetExecute { id, execute: false });
            }
        }
        let i = &mut self.raw.instances[k];
        // FB_RETRY: a pending order is tried again in this call (R-HS-3 with MAX_RETRIALS).
        if !rising {
            if let Some((fb, left)) = i.retry.take() {
                let state = i.state;
                match self.dispatch(fb.clone()) {
                    Ok(reply) => {
                        let ax = self.raw.instances[k].axis;
                        self.raw_placed(k, ax, state, &reply);
                    }
                    Err(r) if r.error_id == FB_ERR_MC_DID_NOT_TAKE_ORDER && left > 1 => {
                        self.raw.instances[k].retry = Some((fb, left - 1));
                    }
                    Err(r) => self.raw_error(k, state, r.error_id),
                }
                return self.raw_out(k);
            }
        }
        // §6.2: an Enable-type FB with cyclic inputs (MC_Power, MC_SetOverride,
        // MC_GroupSetOverride) applies changed inputs while Enable is held, every call.
        let changed =
            call.execute && cyclic_inputs(&call.fb) && i.last_inputs.as_ref() != Some(&call.fb);
        if rising || changed {
            i.last_inputs = cyclic_inputs(&call.fb).then(|| call.fb.clone());
            let state = i.state;
            let Some(ax) = axis else {
                i.state = FbState::Error;
                i.out.error = true;
                i.out.error_id = ErrorId::UNKNOWN_OBJECT;
                return self.raw_out(k);
            };
            if state == FbState::Active && ax != i.axis {
                i.out.error = true;
                i.out.error_id = ERR_SIM_AXIS_REF_CHANGED;
                return self.raw_out(k);
            }
            match self.dispatch(call.fb.clone()) {
                Ok(reply) => self.raw_placed(k, ax, state, &reply),
                Err(r)
                    if r.error_id == FB_ERR_MC_DID_NOT_TAKE_ORDER
                        && self.platform.max_retrials() > 0 =>
                {
                    let i = &mut self.raw.instances[k];
                    i.axis = ax;
                    i.retry = Some((call.fb.clone(), self.platform.max_retrials()));
                    i.out.busy = true;
                }
                Err(r) => self.raw_error(k, state, r.error_id),
            }
        }
        self.raw_out(k)
    }

    /// The order attempt failed: FB-level error (nothing sent, §4.2).
    /// The acknowledgement queue of an FB call: its axis, or its group's channel.
    fn raw_slot(&self, fb: &AxisCommand) -> Option<usize> {
        match fb {
            AxisCommand::Group(g) => self
                .groups
                .index
                .get(g.group())
                .map(|&i| self.set.axes.len() + i),
            _ => fb.axis().and_then(|n| self.set.index.get(n).copied()),
        }
    }

    /// The axis or group name of an acknowledgement queue.
    fn raw_slot_name(&self, slot: usize) -> String {
        match self.set.axes.get(slot) {
            Some(a) => a.name.clone(),
            None => self.groups.list[slot - self.set.axes.len()].name.clone(),
        }
    }

    fn raw_error(&mut self, k: usize, state: FbState, id: ErrorId) {
        let i = &mut self.raw.instances[k];
        i.out.error = true;
        i.out.error_id = id;
        i.out.done = false;
        i.out.command_aborted = false;
        if state != FbState::Active {
            i.state = FbState::Error;
            i.out.busy = false;
            i.out.active = false;
        }
    }

    fn raw_placed(&mut self, k: usize, ax: usize, state: FbState, reply: &AxisReply) {
        let i = &mut self.raw.instances[k];
        if !reply.tracked {
            // Read FBs and MC_Power: no order, done at once.
            i.out = FbOut {
                done: true,
                ..FbOut::default()
            };
            i.state = FbState::Idle;
            return;
        }
        self.raw.owner_of.insert(reply.id, k);
        let placed = self.platform.order_id(reply.id).unwrap_or(0);
        let i = &mut self.raw.instances[k];
        if state == FbState::Active {
            // Re-trigger: the same order number, one more in flight (§4.3).
            if placed != 0 {
                self.platform.keep_order_id(reply.id, i.order_id);
            }
            i.in_flight += 1;
        } else {
            i.order_id = placed;
            i.in_flight = 1;
            // R-HS-2: a latched Done/CommandAborted/Error stays until Execute falls, also
            // across a new trigger.
            i.out = FbOut {
                done: i.out.done,
                command_aborted: i.out.command_aborted,
                error: i.out.error,
                error_id: i.out.error_id,
                ..FbOut::default()
            };
            i.in_velocity_acked = false;
        }
        i.axis = ax;
        i.state = FbState::Active;
        i.out.busy = true;
        i.engine.push(reply.id);
        if i.engine.len() > 8 {
            i.engine.remove(0);
        }
        let order_id = i.order_id;
        self.raw.accepted.push((k, ax, order_id));
    }

    fn raw_out(&self, k: usize) -> FbOut {
        let i = &self.raw.instances[k];
        FbOut {
            instance: i.name.clone(),
            order_id: i.order_id,
            in_flight: i.in_flight,
            fb_state: i.state,
            ..i.out.clone()
        }
    }
}

/// Enable-type FBs whose inputs are read every call while Enable is TRUE (§6.2).
fn cyclic_inputs(fb: &AxisCommand) -> bool {
    matches!(
        fb,
        AxisCommand::Power(_)
            | AxisCommand::SetOverride(_)
            | AxisCommand::Group(crate::group::GroupCommand::GroupSetOverride(_))
    )
}
