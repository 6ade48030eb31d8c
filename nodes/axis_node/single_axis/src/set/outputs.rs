//! What a PLC reads from its FB instances and axes beyond the standard outputs: the outputs
//! of an instance (incl. MC_Power's, probe data, superposition and the added FBs' extra
//! outputs) and the NcToPlc values of the added functions ([`ExtStatus`]).

use super::*;

impl AxisSet {
    /// Recorded data of an MC_TouchProbe instance (after its first accepted edge).
    pub fn probe_outputs(&self, id: CmdId) -> Option<crate::probe::ProbeOutputs> {
        self.fbs.probes.get(&id).copied()
    }

    /// The outputs of an axis' MC_Power instance (Enable-type, §4.1).
    pub fn power_instance_outputs(&self, id: CmdId) -> Option<InstanceOutputs> {
        let a = self.axes.iter().find(|a| a.power_id == Some(id))?;
        let error = !a.power_error.is_none();
        let mut outputs = FbOutputs::default();
        outputs.standard.busy = a.enable;
        outputs.standard.active = a.enable && a.controller_on;
        outputs.standard.error = error;
        outputs.standard.error_id = a.power_error;
        Some(InstanceOutputs {
            axis: str::to_owned(&a.name),
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

    /// The outputs of an admitted instance (MC_Power's too); unknown id → UNKNOWN_OBJECT.
    pub fn read_fb_outputs(&mut self, id: CmdId) -> Result<FbReply, Rejection> {
        if let Some(outputs) = self.power_instance_outputs(id) {
            return Ok(FbReply {
                id,
                value: FbValue::Outputs(Box::new(outputs)),
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
        Ok(FbReply {
            id,
            value: FbValue::Outputs(Box::new(outputs)),
            tracked: false,
        })
    }

    /// Extra outputs of an instance of the added FBs.
    pub fn extra_outputs(&self, id: CmdId) -> Option<ExtraOutputs> {
        let inst = self.fbs.get(id)?;
        match inst.kind {
            FbKind::ExtSetPointGenEnable | FbKind::ExtSetPointGenDisable => {
                Some(ExtraOutputs::ExtSetPointGen {
                    enabled: self.axes[inst.axis].ext.ext_gen.enabled,
                })
            }
            _ => self.fbs.extra.get(&id).copied(),
        }
    }

    /// The scalar NcToPlc values of [`Self::ext_status`] for the snapshot.
    pub fn ext_values(&self, i: usize) -> crate::status::ExtValues {
        let a = &self.axes[i];
        let g = &a.ext.ext_gen;
        let corr = a.ext.x.correction();
        let (f, off) = (a.cfg.encoder_scaling_factor, a.cfg.encoder_offset);
        crate::status::ExtValues {
            abs_phasing_pos: a.abs_phasing_pos(),
            act_pos_without_pos_correction: a.act_pos - corr,
            position_correction: corr,
            drive_set_pos: a.set.pos - corr,
            ext_set_pos: g.fed.pos,
            ext_set_velo: g.fed.vel,
            ext_set_acc: g.fed.acc,
            ext_torque: g.torque_offset,
            encoder_increments: counter32(((a.act_pos - off) / f).round()),
            control_loop_index: a.ext.x.control_loop_index,
        }
    }

    /// Status of the added functions of one axis.
    pub fn ext_status(&self, axis: &str) -> Option<ExtStatus> {
        let &i = self.index.get(axis)?;
        let v = self.ext_values(i);
        let a = &self.axes[i];
        let g = &a.ext.ext_gen;
        Some(ExtStatus {
            abs_phasing_pos: v.abs_phasing_pos,
            phasing_active: a.phasing_active(),
            ext_set_point_gen_enabled: g.enabled,
            ext_set_pos: v.ext_set_pos,
            ext_set_velo: v.ext_set_velo,
            ext_set_acc: v.ext_set_acc,
            ext_set_direction: g.direction,
            ext_torque: v.ext_torque,
            drive_operation_mode: a.ext.x.drive_mode,
            position_correction: v.position_correction,
            act_pos_without_pos_correction: v.act_pos_without_pos_correction,
            drive_set_pos: v.drive_set_pos,
            encoder_scaling_factor: a.cfg.encoder_scaling_factor,
            encoder_offset: a.cfg.encoder_offset,
            encoder_increments: v.encoder_increments,
            control_loop_index: v.control_loop_index,
            accept_blocked_drive: a.ext.accept_blocked_drive,
            nc_io_outputs: a.ext.x.nc_io,
            masters: a
                .coupling
                .filter(|c| c.ext.multi.is_some())
                .map(|c| {
                    c.masters()
                        .map(|m| str::to_owned(&self.axes[m].name))
                        .collect()
                })
                .unwrap_or_default(),
        })
    }
}

/// A 32-bit counter's value at the whole number `n`: `n mod 2³²`. Through `i64` (two's
/// complement wraps as `rem_euclid` does) where it fits, which spares an `fmod` per axis and
/// cycle; `rem_euclid` beyond.
fn counter32(n: f64) -> u32 {
    if n.abs() < 9.0e18 {
        n as i64 as u32
    } else {
        n.rem_euclid(4_294_967_296.0) as u32
    }
}

#[cfg(test)]
mod tests {
    use super::counter32;

    #[test]
    fn counter32_is_rem_euclid_of_two_to_the_32() {
        let two32 = 4_294_967_296.0_f64;
        for n in [
            0.0,
            -0.0,
            1.0,
            -1.0,
            two32 - 1.0,
            two32,
            -two32,
            -two32 - 1.0,
            123_456_789_012.0,
            -123_456_789_012.0,
            8.9e18,
            -8.9e18,
            9.1e18,
            -9.1e18,
            1e300,
            -1e300,
        ] {
            assert_eq!(counter32(n), n.rem_euclid(two32) as u32, "n = {n}");
        }
        for n in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert_eq!(counter32(n), n.rem_euclid(two32) as u32, "n = {n}");
        }
    }
}
