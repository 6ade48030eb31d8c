//! MC_TouchProbe and MC_AbortTrigger (§4.5) (the latch itself is `crate::probe`).

use super::*;

impl AxisSet {
    // ------------------------------------------------------------------ touch probe (§4.5)

    pub(crate) fn probe_slot(name: &str, fb: &str, t: &TriggerRef) -> Result<usize, Rejection> {
        match t.touch_probe {
            TouchProbeUnit::TouchProbe1 => Ok(0),
            TouchProbeUnit::TouchProbe2 => Ok(1),
            TouchProbeUnit::PlcEvent => Ok(2),
            u => Err(reject(
                INVALID_MODE,
                format!("axis '{name}': {fb}: TriggerInput.TouchProbe = {u:?} is not available"),
            )),
        }
    }

    /// MC_TouchProbe (§4.5).
    pub fn touch_probe(&mut self, ax: usize, c: TouchProbe) -> Result<FbReply, Rejection> {
        let fb = "MC_TouchProbe";
        let name = self.axes[ax].name.clone();
        finite(&name, fb, "FirstPosition", c.first_position)?;
        finite(&name, fb, "LastPosition", c.last_position)?;
        let k = Self::probe_slot(&name, fb, &c.trigger_input)?;
        if c.window_only && !c.trigger_input.modulo_positions && c.first_position > c.last_position
        {
            return Err(not_correct(
                &name,
                fb,
                "FirstPosition",
                c.first_position,
                "must not exceed LastPosition (non-modulo window)",
            ));
        }
        self.admit_state(ax, FbClass::TouchProbe, fb)?;
        if self.axes[ax].probes[k].is_some() {
            return Err(reject(
                COMMAND_NOT_PERMITTED,
                format!(
                    "axis '{name}': {fb}: the latch {:?} is already armed (use MC_AbortTrigger)",
                    c.trigger_input.touch_probe
                ),
            ));
        }
        let id = self.fbs.admit(ax, FbKind::TouchProbe, CommandState::Active);
        self.axes[ax].probes[k] = Some(crate::probe::Probe {
            owner: id,
            edge: c.trigger_input.edge,
            mode: c.trigger_input.mode,
            window_only: c.window_only,
            first: c.first_position,
            last: c.last_position,
            modulo_positions: c.trigger_input.modulo_positions,
            plc_event: c.trigger_input.plc_event,
            // An already TRUE PlcEvent is no rising edge.
            plc_prev: c.trigger_input.plc_event,
        });
        Ok(Self::reply(id))
    }

    /// MC_AbortTrigger (§4.5).
    pub fn abort_trigger(&mut self, ax: usize, c: AbortTrigger) -> Result<FbReply, Rejection> {
        let fb = "MC_AbortTrigger";
        let name = self.axes[ax].name.clone();
        let k = Self::probe_slot(&name, fb, &c.trigger_input)?;
        let id = self.fbs.admit(ax, FbKind::AbortTrigger, CommandState::Busy);
        if let Some(p) = self.axes[ax].probes[k].take() {
            self.fbs.aborted(p.owner);
        }
        self.instant_done.push(id);
        Ok(Self::reply(id))
    }

    /// A later call of a running MC_TouchProbe with a new `TriggerInput.PlcEvent` level.
    pub fn probe_plc_event(&mut self, id: CmdId, level: bool) -> Result<FbReply, Rejection> {
        let inst = self.fbs.get(id).copied().ok_or_else(|| {
            reject(
                ErrorId::UNKNOWN_OBJECT,
                format!("unknown command instance {}", id.0),
            )
        })?;
        if inst.kind != FbKind::TouchProbe {
            return Err(reject(
                COMMAND_NOT_PERMITTED,
                format!("command instance {} is not an MC_TouchProbe", id.0),
            ));
        }
        if let Some(p) = self.axes[inst.axis].probes[2]
            .as_mut()
            .filter(|p| p.owner == id)
        {
            p.plc_event = level;
        }
        Ok(Self::reply(id))
    }
}
