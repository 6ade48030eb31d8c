//! Issue 15.2 (xplanar.md §3.2): outside a group a mover has no collision checks, so its
//! command is accepted even when its way runs into another mover. The simulation stays
//! physical: at the contact both movers stop (a crash) and go to Error with E_COLLISION
//! (reaction Abort) and `objectInfo` naming the other mover; footprints never overlap.
//! Inside a group nothing changes (the group's reservations refuse or wait).

mod common;
use common::*;
use motion_core::CommandState;
use planar_engine::errors::*;
use planar_engine::*;

fn two_movers() -> Sim {
    let mut s = Sim::with_movers(&[("M1", 0.0, 240.0), ("M2", 0.0, 0.0)]);
    s.enable("M1");
    s.enable("M2");
    s
}

#[test]
fn outside_a_group_a_contact_is_a_crash() {
    let mut s = two_movers();
    let height = MoverConfig::new("x", 0.0, 0.0, 0.0).height; // 155 mm
                                                              // Accepted: no collision checks outside a group.
    let id = s.ok(mtp("M1", 0.0, 60.0, 0.0));
    assert_eq!(
        s.wait_final(id, 5.0),
        CommandState::Error(E_COLLISION),
        "the move ends in the crash"
    );
    s.steps(200);
    let (m1, m2) = (s.mover("M1"), s.mover("M2"));
    // M1 stopped at the contact: footprints touch, never overlap.
    assert!(
        m1.set_pos.y >= height - 1e-6 && m1.set_pos.y <= height + 1e-3,
        "M1 stopped at {} (contact at {height})",
        m1.set_pos.y
    );
    assert_eq!((m2.set_pos.x, m2.set_pos.y), (0.0, 0.0), "M2 did not move");
    for (m, other) in [(&m1, &m2), (&m2, &m1)] {
        assert_eq!(m.state, PlanarState::Error, "{} in Error", m.name);
        assert_eq!(m.error_id, E_COLLISION, "{}", m.name);
        assert_eq!(
            m.object_info,
            PlanarObjectInfo {
                object_type: PlanarObjectType::Mover,
                id: other.oid
            },
            "{} names the other mover",
            m.name
        );
    }
    // Reset brings both back; nothing overlaps.
    for n in ["M1", "M2"] {
        let r = s.ok(PlanarCommand::MoverReset { mover: n.into() });
        assert_eq!(s.wait_final(r, 5.0), CommandState::Done, "reset {n}");
    }
}

#[test]
fn in_a_group_nothing_changes() {
    let mut s = two_movers();
    s.enable_group("G");
    for n in ["M1", "M2"] {
        s.ok(PlanarCommand::MoverAddToGroup {
            mover: n.into(),
            group: "G".into(),
        });
    }
    s.steps(10);
    let e = s.err(mtp("M1", 0.0, 60.0, 0.0));
    assert_eq!(e.error_id, E_COLLISION, "{e}");
    assert_eq!(s.mover("M1").state, PlanarState::Enabled);
    assert_eq!(s.mover("M2").state, PlanarState::Enabled);
}

/// Issue 15.3 with the part feature: a move to a point outside every part is accepted; the
/// mover's centre stops at the last part's edge (x = 480) and the mover goes to Error with
/// E_COLLISION naming the environment.
#[test]
fn off_the_parts_the_mover_stops_at_the_edge() {
    let mut s = Sim::new(two_parts());
    s.enable("M");
    let id = s.ok(mtp_ref("M", 600.0, 120.0, 0.0, CS));
    assert_stopped_at_edge(&mut s, id, "M", 480.0);
    assert_eq!(s.mover("M").set_pos.y, 120.0, "stopped on its way");
}
