//! §1.3 manual illustration, kept as a conversion test: parts 1–4, CS A and B; Part 3 can
//! be in A or B. While Part 3 lies in A: P1 = (480,480,A) = (0,0,Part3) = (0,480,Part2) =
//! (480,480,Part1). After Part 3 moved to B: P2 = (480,480,B) = (0,0,Part3) = (480,480,Part4).

mod common;
use common::*;
use motion_core::CommandState;
use planar_engine::*;

const A: u32 = 0x0101_0A00;
const B: u32 = 0x0101_0B00;

fn cfg() -> PlanarConfig {
    let part = |n: u32, tiles: Vec<[f64; 2]>, pos: Vec<(u32, u32, f64, f64)>| PartConfig {
        name: format!("part{n}"),
        oid: 0x0101_0000 + n,
        tiles,
        positions: pos
            .into_iter()
            .map(|(i, cs, x, y)| (i, PartPositionConfig { cs, x, y }))
            .collect(),
        initial_index: 1,
    };
    let quad = vec![[0.0, 0.0], [240.0, 0.0], [0.0, 240.0], [240.0, 240.0]];
    let mut m = MoverConfig::new("M", 120.0, 120.0, 0.0);
    m.part_oid = 0x0101_0003;
    PlanarConfig {
        coordinate_systems: vec![A, B],
        parts: vec![
            part(1, quad.clone(), vec![(1, A, 0.0, 0.0)]),
            part(2, quad.clone(), vec![(1, A, 480.0, 0.0)]),
            part(
                3,
                vec![[0.0, 0.0]],
                vec![(1, A, 480.0, 480.0), (2, B, 480.0, 480.0)],
            ),
            part(4, quad, vec![(1, B, 0.0, 0.0)]),
        ],
        environment: EnvironmentConfig {
            name: "env".into(),
            oid: 0x0101_0E01,
            processing_unit_oid: 0x0101_0E02,
        },
        movers: vec![m],
        ..Default::default()
    }
}

fn local(s: &Sim, p: &PositionXYC, part: &str) -> Option<(f64, f64)> {
    s.eng.to_part_local(p, part).unwrap().map(|q| (q.x, q.y))
}

#[test]
fn manual_illustration_of_part_systems() {
    let mut s = Sim::new(cfg());
    let p1 = PositionXYC::with_ref(480.0, 480.0, 0.0, A);
    assert_eq!(local(&s, &p1, "part3"), Some((0.0, 0.0)));
    assert_eq!(local(&s, &p1, "part2"), Some((0.0, 480.0)));
    assert_eq!(local(&s, &p1, "part1"), Some((480.0, 480.0)));
    assert_eq!(local(&s, &p1, "part4"), None, "part 4 lies in B");
    let back = s
        .eng
        .resolve_position(&PositionXYC::with_ref(0.0, 480.0, 0.0, 0x0101_0002))
        .unwrap();
    assert_eq!((back.x, back.y, back.reference_id), (480.0, 480.0, A));
    // The mover rides on part 3 into B.
    s.ok(PlanarCommand::PartInitialize {
        part: "part3".into(),
        part_oid: 0x0101_0003,
    });
    let a = s.ok(PlanarCommand::ActivatePosition {
        part: "part3".into(),
        position_index: 2,
    });
    assert_eq!(s.wait_final(a, 2.0), CommandState::Done);
    let p2 = PositionXYC::with_ref(480.0, 480.0, 0.0, B);
    assert_eq!(local(&s, &p2, "part3"), Some((0.0, 0.0)));
    assert_eq!(local(&s, &p2, "part4"), Some((480.0, 480.0)));
    assert_eq!(local(&s, &p2, "part1"), None);
    let part3_origin = s
        .eng
        .resolve_position(&PositionXYC::with_ref(0.0, 0.0, 0.0, 0x0101_0003))
        .unwrap();
    assert_eq!(
        (part3_origin.x, part3_origin.y, part3_origin.reference_id),
        (480.0, 480.0, B)
    );
    let m = s.mover("M");
    assert_eq!((m.coordinate_system_oid, m.part_oid), (B, 0x0101_0003));
    assert_pos(&m, 600.0, 600.0);
    // Several CS: ReferenceId 0 is rejected, unknown ids too.
    assert_eq!(
        s.eng
            .resolve_position(&PositionXYC::new(1.0, 1.0, 0.0))
            .unwrap_err()
            .error_id,
        errors::E_INVALID_REFERENCE_ID
    );
    assert_eq!(
        s.eng
            .resolve_position(&PositionXYC::with_ref(1.0, 1.0, 0.0, 77))
            .unwrap_err()
            .error_id,
        errors::E_INVALID_REFERENCE_ID
    );
}
