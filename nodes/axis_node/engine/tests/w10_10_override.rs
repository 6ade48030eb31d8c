//! collision_avoidance.md §10.10 "Override" (MC_GroupSetOverride, §1.11, §5.18).

mod ca_common;
use axis_engine::ca::types::errors::*;
use axis_engine::ca::*;
use axis_engine::ReplyValue;
use ca_common::*;

fn set(r: &mut CaRig, f: f64) -> f64 {
    r.step();
    let rep = r
        .ca(CaCommand::GroupSetOverride {
            group: G.into(),
            enable: true,
            vel_factor: f,
        })
        .unwrap();
    assert!(matches!(
        *match rep.value {
            ReplyValue::Ca(v) => v,
            _ => panic!(),
        },
        CaValue::Override { enabled: true, .. }
    ));
    r.steps(200);
    r.group().act_override_factor
}

#[test]
fn factor_is_clamped_to_0_1() {
    let mut r = CaRig::new(&[("A", 0.0)], open(5000.0));
    assert_eq!(set(&mut r, 1.5), 1.0);
    assert_eq!(set(&mut r, -0.2), 0.0);
    assert_eq!(
        r.err(CaCommand::GroupSetOverride {
            group: G.into(),
            enable: true,
            vel_factor: f64::NAN
        }),
        PARAMETER_NOT_CORRECT
    );
}

#[test]
fn half_override_during_a_1000_mm_s_move_cruises_at_500() {
    let mut r = CaRig::new(&[("A", 0.0)], open(10000.0));
    r.mv_abs("A", 9000.0, 1000.0);
    r.steps(500);
    assert!((r.axis("A").velocity - 1000.0).abs() < 1e-6);
    r.ok(CaCommand::GroupSetOverride {
        group: G.into(),
        enable: true,
        vel_factor: 0.5,
    });
    r.steps(50);
    let f = r.group().act_override_factor;
    assert!((f - 0.75).abs() < 0.02, "linear ramp over 0.1 s: {f}");
    r.steps(400);
    assert_eq!(r.group().act_override_factor, 0.5);
    assert!(
        (r.axis("A").velocity - 500.0).abs() < 1e-3,
        "cruise 500: {}",
        r.axis("A").velocity
    );
}
