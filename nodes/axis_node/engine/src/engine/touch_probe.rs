//! MC_TouchProbe and MC_AbortTrigger (§4.5) (the latch itself is `crate::probe`).

use super::*;

impl AxisEngine {
    // ------------------------------------------------------------------ touch probe (§4.5)

    pub(super) fn probe_slot(name: &str, fb: &str, t: &TriggerRef) -> Result<usize, Rejection> {
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

    pub(super) fn touch_probe(&mut self, ax: usize, c: TouchProbe) -> Result<AxisReply, Rejection> {
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

    pub(super) fn abort_trigger(
        &mut self,
        ax: usize,
        c: AbortTrigger,
    ) -> Result<AxisReply, Rejection> {
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

    pub(super) fn probe_plc_event(
        &mut self,
        id: CmdId,
        level: bool,
    ) -> Result<AxisReply, Rejection> {
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

    /// Recorded data of an MC_TouchProbe instance (after its first accepted edge).
    pub fn probe_outputs(&self, id: CmdId) -> Option<crate::probe::ProbeOutputs> {
        self.fbs.probes.get(&id).copied()
    }

    /// The outputs of an axis' MC_Power instance (Enable-type, §4.1).
    pub(super) fn power_instance_outputs(&self, id: CmdId) -> Option<InstanceOutputs> {
        let a = self.axes.iter().find(|a| a.power_id == Some(id))?;
        let error = !a.power_error.is_none();
        let mut outputs = FbOutputs::default();
        outputs.standard.busy = a.enable;
        outputs.standard.active = a.enable && a.controller_on;
        outputs.standard.error = error;
        outputs.standard.error_id = a.power_error;
        Some(InstanceOutputs {
            axis: a.name.clone(),
            kind: FbKind::Power,
            outputs,
            superimposed: None,
            probe: None,
            extra: Some(ExtraOutputs::Power {
                status: a.status,
                valid: a.enable && !error,
            }),
        })
    }

    pub(super) fn read_fb_outputs(&mut self, id: CmdId) -> Result<AxisReply, Rejection> {
        if let Some(outputs) = self.power_instance_outputs(id) {
            return Ok(AxisReply {
                id,
                value: ReplyValue::Outputs(Box::new(outputs)),
                tracked: false,
            });
        }
        let (axis, kind) = self
            .instance(id)
            .map(|(a, k)| (a.to_string(), k))
            .ok_or_else(|| {
                reject(
                    ErrorId::UNKNOWN_OBJECT,
                    format!("unknown command instance {}", id.0),
                )
            })?;
        let outputs = InstanceOutputs {
            axis,
            kind,
            outputs: self.fb_outputs(id).unwrap_or_default(),
            superimposed: self.superimposed_outputs(id),
            probe: self.probe_outputs(id),
            extra: self.extra_outputs(id),
        };
        // The instance's own id, so the reply names what was read.
        Ok(AxisReply {
            id,
            value: ReplyValue::Outputs(Box::new(outputs)),
            tracked: false,
        })
    }
}
