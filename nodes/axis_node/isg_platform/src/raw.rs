//! Raw FB layer (plcopen_platform.md §12.2, §4, §6.3): exact PLC emulation for tests.
//!
//! [`RawLayer::fb_cycle`] runs one PLC cycle: the listed FB instances are called in the
//! given order with their inputs (instances not listed are not called), then the MC runs one
//! cycle. Each instance has the FB_IDLE / FB_ACTIVE / FB_ERROR states of R-FB-1, keeps its
//! order number (§4.3; a re-trigger while ACTIVE reuses it, R-FB-3) and takes only the
//! acknowledgements of its own orders from its axis' single acknowledgement queue (R-HS-5):
//! an acknowledgement nobody consumes blocks all later ones of that axis ("clogging"); after
//! more than 2 cycles at the head, warning 4906 is recorded. Done/CommandAborted/Error are
//! latched until Execute falls (R-HS-2).
//!
//! The layer drives an engine through [`RawHost`] (implemented by the axis engine for its
//! command type): it places orders, releases instances, runs MC cycles and names the
//! channels. Part 4 group FBs work the same way on their group's channel: one
//! acknowledgement queue per group (after the axes' queues), the channel's order slot of
//! R-HS-3/R-HS-4, order numbers, clogging with the group's name in the warning.

mod state;

use crate::ids::*;
use crate::{Platform, RawWarning};
use motion_core::{CmdId, CommandEvent, CommandState, ErrorId, Rejection, Tick};
use state::{Ack, Inst};
use std::collections::VecDeque;

pub use state::{AckKind, FbCall, FbOut, FbState, RawLayer};

/// The engine a raw FB layer drives (plcopen_platform.md §12.2).
pub trait RawHost {
    /// The engine's FB call (an Execute edge or the current inputs of an Enable-type FB).
    type Call: Clone + PartialEq;
    /// Places a call: the instance id and whether it is tracked (an order with a lifetime);
    /// a refusal is the FB-level error.
    fn place(&mut self, call: Self::Call) -> Result<(CmdId, bool), Rejection>;
    /// Execute of instance `id` fell (MC_Stop / MC_GroupStop release their axis or group).
    fn release(&mut self, id: CmdId);
    /// One MC cycle; its events go to `events`.
    fn mc_cycle(&mut self, tick: Tick, events: &mut Vec<CommandEvent>);
    /// The handshake events the calls of this PLC cycle produced (aborts of older orders).
    fn take_events(&mut self, events: &mut Vec<CommandEvent>);
    /// The acknowledgement channel of a call: its axis, or its group's channel after the axes.
    fn channel(&self, call: &Self::Call) -> Option<usize>;
    /// The number of channels (axes + groups).
    fn channels(&self) -> usize;
    /// The axis or group name of a channel.
    fn channel_name(&self, channel: usize) -> String;
    /// Enable-type FBs whose inputs are read every call while Enable is TRUE (§6.2).
    fn cyclic_inputs(call: &Self::Call) -> bool;
    /// InVelocity of instance `id`.
    fn in_velocity(&self, id: CmdId) -> bool;
    /// The ErrorID instance `id` shows for `e` under the profile.
    fn shown_error(&self, id: CmdId, e: ErrorId) -> ErrorId;
    /// The platform (order numbers, `MAX_RETRIALS`).
    fn platform(&mut self) -> &mut Platform;
}

impl<C: Clone + PartialEq> RawLayer<C> {
    /// One PLC cycle of the raw FB layer (§12.2): calls in order, then one MC cycle. Events of
    /// commands not owned by raw instances are appended to `events`.
    pub fn fb_cycle<H: RawHost<Call = C>>(
        &mut self,
        host: &mut H,
        tick: Tick,
        calls: &[FbCall<C>],
        events: &mut Vec<CommandEvent>,
    ) -> Vec<FbOut> {
        // Acknowledgement queues: the axes, then the groups' channels.
        let n_slots = host.channels();
        if self.acks.len() != n_slots {
            self.acks = vec![VecDeque::new(); n_slots];
            self.clog_warned = vec![None; n_slots];
        }
        let mut outs = Vec::with_capacity(calls.len());
        for call in calls {
            outs.push(self.call(host, call));
        }
        // (3) the MC consumes the orders: aborts caused by them first, then ACCEPTED, then
        // what the cycle itself produces (`step` routes raw-owned events to their queues).
        let from = events.len();
        host.take_events(events);
        let mut accepted = std::mem::take(&mut self.accepted);
        // An order overwritten in its own cycle (MC_Stop / MC_GroupStop, R-HS-4) is
        // acknowledged ACCEPTED before its ABORTED.
        for e in &events[from..] {
            let owner = self.owner_of.get(&e.id).copied();
            if let Some(p) = owner
                .filter(|_| e.state.is_final())
                .and_then(|i| accepted.iter().position(|a| a.0 == i))
            {
                let a = accepted.remove(p);
                self.raw_accepted(a);
            }
        }
        self.route(events, from, &|id, e| host.shown_error(id, e));
        for a in accepted {
            self.raw_accepted(a);
        }
        // The MC cycle; its events of raw-owned commands become acknowledgements.
        let from = events.len();
        host.mc_cycle(tick, events);
        self.route(events, from, &|id, e| host.shown_error(id, e));
        // InVelocity acknowledgements.
        for k in 0..self.instances.len() {
            let i = &self.instances[k];
            if i.state != FbState::Active || i.in_velocity_acked {
                continue;
            }
            let iv = i.engine.last().is_some_and(|&id| host.in_velocity(id));
            if iv {
                let (axis, order_id) = (i.axis, i.order_id);
                self.instances[k].in_velocity_acked = true;
                self.acks[axis].push_back(Ack {
                    owner: k,
                    kind: AckKind::InVelocity,
                    posted: self.cycle,
                    order_id,
                });
            }
        }
        // Clog watchdog: the same acknowledgement at the head for more than 2 cycles.
        for ax in 0..n_slots {
            if let Some(h) = self.acks[ax].front().copied() {
                let key = Some((h.owner, h.order_id));
                if self.cycle > h.posted + 2 && self.clog_warned[ax] != key {
                    self.clog_warned[ax] = key;
                    self.warnings.push(RawWarning {
                        cycle: self.cycle,
                        axis: host.channel_name(ax),
                        id: ERR_SIM_HLI_ACK_CLOG,
                        order_id: h.order_id,
                    });
                }
            }
        }
        self.cycle += 1;
        outs
    }

    /// Posts the ACCEPTED acknowledgement of an order placed in this cycle.
    fn raw_accepted(&mut self, (inst, axis, order_id): (usize, usize, u32)) {
        self.acks[axis].push_back(Ack {
            owner: inst,
            kind: AckKind::Accepted,
            posted: self.cycle,
            order_id,
        });
    }

    /// Warnings of the raw layer so far (4906).
    pub fn warnings(&self) -> &[RawWarning] {
        &self.warnings
    }

    /// After an MC cycle (in [`Self::fb_cycle`] or a free-running one between `~/fb/cycle`
    /// requests): the events of raw-owned commands from `events[from..]` become
    /// acknowledgements in their queues; `shown` gives the ErrorID the profile shows. No
    /// allocation.
    pub fn route(
        &mut self,
        events: &mut Vec<CommandEvent>,
        from: usize,
        shown: &dyn Fn(CmdId, ErrorId) -> ErrorId,
    ) {
        if self.owner_of.is_empty() {
            return;
        }
        let mut k = from;
        while k < events.len() {
            if self.raw_ack(events[k], shown) {
                events.remove(k);
            } else {
                k += 1;
            }
        }
    }

    /// Queues the acknowledgement of a raw-owned command's final event; false if the command
    /// is not raw-owned (the event stays with the caller).
    fn raw_ack(&mut self, e: CommandEvent, shown: &dyn Fn(CmdId, ErrorId) -> ErrorId) -> bool {
        let Some(&k) = self.owner_of.get(&e.id) else {
            return false;
        };
        let kind = match e.state {
            CommandState::Done => AckKind::Done,
            CommandState::Aborted => AckKind::Aborted,
            CommandState::Error(id) => AckKind::Error(shown(e.id, id)),
            // The admission is acknowledged as ACCEPTED by the raw layer itself; the axis
            // engine never ends an instance without an output (Ended).
            CommandState::Busy | CommandState::Active | CommandState::Ended => return true,
        };
        let i = &self.instances[k];
        let (axis, order_id) = (i.axis, i.order_id);
        self.acks[axis].push_back(Ack {
            owner: k,
            kind,
            posted: self.cycle,
            order_id,
        });
        true
    }

    fn call<H: RawHost<Call = C>>(&mut self, host: &mut H, call: &FbCall<C>) -> FbOut {
        let k = match self.by_name.get(&call.instance) {
            Some(&k) => k,
            None => {
                let k = self.instances.len();
                self.instances.push(Inst::new(call.instance.clone()));
                self.by_name.insert(call.instance.clone(), k);
                k
            }
        };
        let axis = host.channel(&call.fb);
        // Consume this instance's acknowledgements at the head of its axis' queue.
        let qa = self.instances[k].axis;
        if self.instances[k].state == FbState::Active {
            while let Some(h) = self.acks[qa].front().copied() {
                if h.owner != k {
                    break;
                }
                self.acks[qa].pop_front();
                if self.clog_warned[qa].is_some_and(|w| w.0 == k) {
                    self.clog_warned[qa] = None;
                }
                let i = &mut self.instances[k];
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
        let i = &mut self.instances[k];
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
                host.release(id);
            }
        }
        let i = &mut self.instances[k];
        // FB_RETRY: a pending order is tried again in this call (R-HS-3 with MAX_RETRIALS).
        if !rising {
            if let Some((fb, left)) = i.retry.take() {
                let state = i.state;
                match host.place(fb.clone()) {
                    Ok(reply) => {
                        let ax = self.instances[k].axis;
                        self.raw_placed(host, k, ax, state, reply);
                    }
                    Err(r) if r.error_id == FB_ERR_MC_DID_NOT_TAKE_ORDER && left > 1 => {
                        self.instances[k].retry = Some((fb, left - 1));
                    }
                    Err(r) => self.raw_error(k, state, r.error_id),
                }
                return self.raw_out(k);
            }
        }
        // §6.2: an Enable-type FB with cyclic inputs (MC_Power, MC_SetOverride,
        // MC_GroupSetOverride) applies changed inputs while Enable is held, every call.
        let changed =
            call.execute && H::cyclic_inputs(&call.fb) && i.last_inputs.as_ref() != Some(&call.fb);
        if rising || changed {
            i.last_inputs = H::cyclic_inputs(&call.fb).then(|| call.fb.clone());
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
            match host.place(call.fb.clone()) {
                Ok(reply) => self.raw_placed(host, k, ax, state, reply),
                Err(r)
                    if r.error_id == FB_ERR_MC_DID_NOT_TAKE_ORDER
                        && host.platform().max_retrials() > 0 =>
                {
                    let i = &mut self.instances[k];
                    i.axis = ax;
                    i.retry = Some((call.fb.clone(), host.platform().max_retrials()));
                    i.out.busy = true;
                }
                Err(r) => self.raw_error(k, state, r.error_id),
            }
        }
        self.raw_out(k)
    }

    /// The order attempt failed: FB-level error (nothing sent, §4.2).
    fn raw_error(&mut self, k: usize, state: FbState, id: ErrorId) {
        let i = &mut self.instances[k];
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

    fn raw_placed<H: RawHost<Call = C>>(
        &mut self,
        host: &mut H,
        k: usize,
        ax: usize,
        state: FbState,
        (id, tracked): (CmdId, bool),
    ) {
        let i = &mut self.instances[k];
        if !tracked {
            // Read FBs and MC_Power: no order, done at once.
            i.out = FbOut {
                done: true,
                ..FbOut::default()
            };
            i.state = FbState::Idle;
            return;
        }
        self.owner_of.insert(id, k);
        let placed = host.platform().order_id(id).unwrap_or(0);
        let i = &mut self.instances[k];
        if state == FbState::Active {
            // Re-trigger: the same order number, one more in flight (§4.3).
            if placed != 0 {
                host.platform().keep_order_id(id, i.order_id);
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
        i.engine.push(id);
        if i.engine.len() > 8 {
            i.engine.remove(0);
        }
        let order_id = i.order_id;
        self.accepted.push((k, ax, order_id));
    }

    fn raw_out(&self, k: usize) -> FbOut {
        let i = &self.instances[k];
        FbOut {
            instance: i.name.clone(),
            order_id: i.order_id,
            in_flight: i.in_flight,
            fb_state: i.state,
            ..i.out.clone()
        }
    }
}
