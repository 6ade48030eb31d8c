//! collision_avoidance.md §10.1 "Basics: ten movers queue on a 3000 mm ring".

mod ca_common;
use axis_engine::ca::*;
use ca_common::*;
use motion_core::CommandState;

const START: [f64; 10] = [
    2400.0, 2000.0, 1800.0, 1500.0, 1450.0, 1000.0, 800.0, 500.0, 200.0, 100.0,
];

fn names() -> Vec<String> {
    (1..=10).map(|i| format!("M{i}")).collect()
}

fn rig() -> CaRig {
    let n = names();
    let m: Vec<(&str, f64)> = n.iter().map(|s| s.as_str()).zip(START).collect();
    CaRig::new(&m, ring(3000.0))
}

#[test]
fn step1_2_order_by_position_and_wrap_gap_nothing_moves_on_enable() {
    let mut r = rig();
    let g = r.group();
    assert_eq!(g.state, GroupState::GroupStandby, "step 2: Standby");
    assert_eq!(g.group_axes_count, 10);
    let order: Vec<_> = g.axes.iter().map(|a| a.name.clone()).collect();
    assert_eq!(order, names(), "step 1: M1 front ... M10 rear");
    assert_eq!(g.axes[0].predecessor.as_deref(), Some("M10"));
    assert!(
        (g.axes[0].gap_actual - 700.0).abs() < 1e-9,
        "M1 gap across the seam = 700"
    );
    r.steps(100);
    assert!(
        (r.pos("M5") - 1450.0).abs() < 1e-12,
        "step 2: nothing moves"
    );
    assert!(
        (r.axis("M5").gap_actual - 50.0).abs() < 1e-9,
        "M5's gap stays 50"
    );
}

#[test]
fn step3_4_all_to_2500_queue_behind_m1_then_group_halt() {
    let mut r = rig();
    let ids: Vec<_> = names()
        .iter()
        .map(|n| r.mv_abs(n, 2500.0, 1000.0))
        .collect();
    assert_eq!(r.state(), GroupState::GroupMoving);
    let mut m5_min = f64::INFINITY;
    let mut others_min = f64::INFINITY;
    let mut reached_100 = false;
    for _ in 0..3000 {
        r.step();
        let g = r.group();
        for a in &g.axes {
            if a.name == "M5" {
                if reached_100 {
                    m5_min = m5_min.min(a.gap_actual - 100.0);
                } else {
                    m5_min = m5_min.min(a.gap_actual - 50.0);
                    reached_100 = a.gap_actual >= 100.0 - 1e-6;
                }
            } else if a.name != "M1" {
                others_min = others_min.min(a.gap_actual - a.gap_target);
            }
        }
    }
    assert!(
        m5_min >= -1e-6,
        "M5's gap never below 50, then never below 100: {m5_min}"
    );
    assert!(
        others_min >= -1e-6,
        "all other gaps ≥ 100 − 1e-6: {others_min}"
    );
    assert_eq!(r.cmd_state(ids[0]), CommandState::Done, "M1 Done");
    assert!((r.pos("M1") - 2500.0).abs() <= 1e-9, "M1 at 2500.000");
    let expect = [
        2400.0, 2300.0, 2200.0, 2100.0, 2000.0, 1900.0, 1800.0, 1700.0, 1600.0,
    ];
    for (i, x) in expect.iter().enumerate() {
        let n = format!("M{}", i + 2);
        assert!(
            (r.pos(&n) - x).abs() <= 1e-3,
            "{n} rests at {x}: {}",
            r.pos(&n)
        );
        assert_eq!(
            r.cmd_state(ids[i + 1]),
            CommandState::Active,
            "{n} Busy and Active"
        );
    }
    let g = r.group();
    assert_eq!(
        g.state,
        GroupState::GroupMoving,
        "Moving while commands wait"
    );
    assert!(g.all_axes_standing, "AllAxesStanding once settled");
    assert!(
        (r.axis("M1").gap_actual - 2100.0).abs() <= 1e-3,
        "wrap gap 2100"
    );
    // Step 4: MC_GroupHalt.
    let h = r.ok(CaCommand::GroupHalt {
        group: G.into(),
        deceleration: McLreal::Unset,
        jerk: McLreal::Unset,
    });
    r.step();
    for id in &ids[1..] {
        assert_eq!(
            r.cmd_state(*id),
            CommandState::Aborted,
            "waiting commands CommandAborted"
        );
    }
    assert_eq!(r.cmd_state(h), CommandState::Done, "GroupHalt Done");
    assert_eq!(r.state(), GroupState::GroupStandby, "group Standby");
}

#[test]
fn tie_rule_last_added_is_front() {
    let mut r = CaRig::ungrouped(&[("A", 0.0), ("B", 0.0)], open(5000.0));
    r.add("A", 1).unwrap();
    r.add("B", 2).unwrap();
    r.enable();
    r.step();
    assert_eq!(r.group().axes[0].name, "B", "B is the front axis");
    let a = r.mv_abs("A", 500.0, 1000.0);
    let b = r.mv_abs("B", 500.0, 1000.0);
    r.steps(2000);
    assert_eq!(r.cmd_state(b), CommandState::Done);
    assert!((r.pos("B") - 500.0).abs() < 1e-9);
    assert_eq!(r.cmd_state(a), CommandState::Active, "A Busy");
    assert!(
        (r.pos("A") - 400.0).abs() < 1e-3,
        "A at 400: {}",
        r.pos("A")
    );
}
