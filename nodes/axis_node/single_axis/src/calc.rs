//! FBs without axis and without Execute: MC_CalcDynamicsByRampTime (single_axis.md §4.7.3,
//! W12) and MC_OverrideFilter (§4.7.4, W13).

use crate::error_ids::PARAMETER_NOT_CORRECT;
use motion_core::Rejection;

/// Outputs of MC_CalcDynamicsByRampTime.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RampDynamics {
    /// Acceleration \[u/s²\].
    pub acceleration: f64,
    /// Deceleration (= Acceleration) \[u/s²\].
    pub deceleration: f64,
    /// Jerk \[u/s³\].
    pub jerk: f64,
}

/// MC_CalcDynamicsByRampTime: `t1 = t·(1−s)/(2−s)`, `t2 = t·s/(2−s)`,
/// `Acceleration = Velocity/(t1 + t2)`, `Jerk = Acceleration/t1` (derived formula of §4.7.3).
/// Velocity ≤ 0, RampTime ≤ 0 or Stiffness ∉ [0, 1) → Error 0x4B06.
pub fn calc_dynamics_by_ramp_time(
    velocity: f64,
    ramp_time: f64,
    stiffness: f64,
) -> Result<RampDynamics, Rejection> {
    for (f, v) in [
        ("Velocity", velocity),
        ("RampTime", ramp_time),
        ("Stiffness", stiffness),
    ] {
        if !v.is_finite() {
            return Err(Rejection::not_finite("MC_CalcDynamicsByRampTime", f, v));
        }
    }
    let bad = |f: &str, v: f64, need: &str| {
        Rejection::new(
            PARAMETER_NOT_CORRECT,
            format!("MC_CalcDynamicsByRampTime: {f} = {v} {need}"),
        )
    };
    if velocity <= 0.0 {
        return Err(bad("Velocity", velocity, "must be > 0"));
    }
    if ramp_time <= 0.0 {
        return Err(bad("RampTime", ramp_time, "must be > 0"));
    }
    if !(0.0..1.0).contains(&stiffness) {
        return Err(bad("Stiffness", stiffness, "must be in [0, 1)"));
    }
    let t1 = ramp_time * (1.0 - stiffness) / (2.0 - stiffness);
    let t2 = ramp_time * stiffness / (2.0 - stiffness);
    let acceleration = velocity / (t1 + t2);
    Ok(RampDynamics {
        acceleration,
        deceleration: acceleration,
        jerk: acceleration / t1,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use motion_core::ErrorId;

    /// W12: V 100, t 1: s 0 → 200/200/400; s 0.5 → 150/150/450.
    #[test]
    fn w12_examples() {
        let d = calc_dynamics_by_ramp_time(100.0, 1.0, 0.0).unwrap();
        assert!((d.acceleration - 200.0).abs() < 1e-9 && (d.deceleration - 200.0).abs() < 1e-9);
        assert!((d.jerk - 400.0).abs() < 1e-9);
        let d = calc_dynamics_by_ramp_time(100.0, 1.0, 0.5).unwrap();
        assert!((d.acceleration - 150.0).abs() < 1e-9 && (d.jerk - 450.0).abs() < 1e-9);
        // The phases: s 0 → t1 = t/2, t2 = 0; s 0.5 → t1 = t2 = t/3; s 0.99 → t1 ≈ 0, t2 ≈ t.
        let d = calc_dynamics_by_ramp_time(100.0, 1.0, 0.99).unwrap();
        let t1 = d.acceleration / d.jerk;
        assert!(t1 < 0.01 && (100.0 / d.acceleration - t1 - 0.98).abs() < 0.02);
        // A jerk-limited ramp with these values reaches 100 in exactly the ramp time.
        for s in [0.0, 0.3, 0.5, 0.9] {
            let d = calc_dynamics_by_ramp_time(100.0, 2.0, s).unwrap();
            let t = 100.0 / d.acceleration + d.acceleration / d.jerk;
            assert!((t - 2.0).abs() < 1e-9, "stiffness {s}: {t}");
        }
    }

    #[test]
    fn errors() {
        for (v, t, s) in [
            (0.0, 1.0, 0.5),
            (100.0, 0.0, 0.5),
            (100.0, 1.0, 1.0),
            (100.0, 1.0, -0.1),
        ] {
            assert_eq!(
                calc_dynamics_by_ramp_time(v, t, s).unwrap_err().error_id,
                PARAMETER_NOT_CORRECT
            );
        }
        assert_eq!(
            calc_dynamics_by_ramp_time(f64::NAN, 1.0, 0.5)
                .unwrap_err()
                .error_id,
            ErrorId::NOT_FINITE
        );
    }
}

/// MC_OverrideFilter (§4.7.4, W13): a filter instance (FB without axis and Execute).
/// Call [`OverrideFilter::call`] every PLC cycle with the raw value and the current time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OverrideFilter {
    /// LowerOverrideThreshold (digits, default 0).
    pub lower: i32,
    /// UpperOverrideThreshold (digits, default 32767).
    pub upper: i32,
    /// OverrideSteps (default 200 → 0.5 %).
    pub steps: u32,
    /// OverrideRecoveryTime \[s\] (default 0.150).
    pub recovery_time: f64,
    level: Option<u32>,
    changed_at: f64,
}

impl Default for OverrideFilter {
    fn default() -> Self {
        OverrideFilter {
            lower: 0,
            upper: 32767,
            steps: 200,
            recovery_time: 0.150,
            level: None,
            changed_at: f64::NEG_INFINITY,
        }
    }
}

/// Outputs of MC_OverrideFilter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilteredOverride {
    /// OverrideValueFiltered (0..1 000 000).
    pub value: u32,
    /// OverridePercentFiltered (0..100).
    pub percent: f64,
}

impl OverrideFilter {
    /// One call: clamp, quantize to `steps` levels; a new level is taken over only
    /// `recovery_time` after the previous output change, except 0 % and 100 % (at once).
    /// OverrideSteps ≤ 1 or Lower ≥ Upper → Error 0x4B06 (MC_ERROR_PARAMETER_NOT_CORRECT).
    pub fn call(&mut self, raw: i32, now: f64) -> Result<FilteredOverride, Rejection> {
        if self.steps <= 1 {
            return Err(Rejection::new(
                PARAMETER_NOT_CORRECT,
                format!(
                    "MC_OverrideFilter: OverrideSteps = {} must be > 1",
                    self.steps
                ),
            ));
        }
        if self.lower >= self.upper {
            return Err(Rejection::new(
                PARAMETER_NOT_CORRECT,
                format!("MC_OverrideFilter: LowerOverrideThreshold = {} must be below UpperOverrideThreshold = {}", self.lower, self.upper),
            ));
        }
        if !(self.recovery_time.is_finite() && self.recovery_time >= 0.0 && now.is_finite()) {
            return Err(Rejection::new(
                PARAMETER_NOT_CORRECT,
                format!(
                    "MC_OverrideFilter: OverrideRecoveryTime = {} / time {now} invalid",
                    self.recovery_time
                ),
            ));
        }
        let f = (raw.clamp(self.lower, self.upper) - self.lower) as f64
            / (self.upper - self.lower) as f64;
        let wanted = ((f * self.steps as f64).floor() as u32).min(self.steps);
        let take = match self.level {
            None => true,
            Some(l) if l == wanted => false,
            Some(_) => {
                wanted == 0
                    || wanted == self.steps
                    || now - self.changed_at >= self.recovery_time - 1e-12
            }
        };
        if take {
            if self.level != Some(wanted) {
                self.changed_at = now;
            }
            self.level = Some(wanted);
        }
        let level = self.level.unwrap_or(wanted) as u64;
        Ok(FilteredOverride {
            value: (1_000_000 * level / self.steps as u64) as u32,
            percent: 100.0 * level as f64 / self.steps as f64,
        })
    }
}

#[cfg(test)]
mod override_filter_tests {
    use super::*;

    /// W13: raw 16384 → 50 % / 500 000; 50 → 60 % only 150 ms after the previous change;
    /// 0 % and 100 % at once; OverrideSteps 1 → error.
    #[test]
    fn w13() {
        let mut f = OverrideFilter::default();
        let o = f.call(16384, 0.0).unwrap();
        assert_eq!((o.value, o.percent), (500_000, 50.0));
        let raw60 = (0.6 * 32767.0f64).ceil() as i32;
        assert_eq!(
            f.call(raw60, 0.1).unwrap().percent,
            50.0,
            "within the recovery time"
        );
        assert_eq!(
            f.call(raw60, 0.15).unwrap().percent,
            60.0,
            "150 ms after the last change"
        );
        assert_eq!(f.call(100, 0.16).unwrap().percent, 0.0, "0 % at once");
        assert_eq!(f.call(32767, 0.17).unwrap().percent, 100.0, "100 % at once");
        assert_eq!(f.call(16384, 0.2).unwrap().percent, 100.0);
        assert_eq!(f.call(16384, 0.32).unwrap().percent, 50.0);
        let mut bad = OverrideFilter {
            steps: 1,
            ..Default::default()
        };
        assert_eq!(
            bad.call(0, 0.0).unwrap_err().error_id,
            PARAMETER_NOT_CORRECT
        );
        let mut bad = OverrideFilter {
            lower: 5,
            upper: 5,
            ..Default::default()
        };
        assert_eq!(
            bad.call(0, 0.0).unwrap_err().error_id,
            PARAMETER_NOT_CORRECT
        );
    }
}
