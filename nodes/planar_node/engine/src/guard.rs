//! The physical no-overlap guard: a uniform grid over stop envelopes (xplanar.md §5.11,
//! task requirement "movers never overlap").
//!
//! Invariant: the *envelopes* of all movers are pairwise disjoint, where a mover's envelope
//! is the area its footprint sweeps while stopping from its current state with maximum
//! dynamics. A mover may take its next set point only if the envelope of that new state is
//! free; otherwise it follows the stop whose envelope it already owns. Footprints lie inside
//! envelopes, so footprints never overlap. Cost: one grid insertion per mover and a few SAT
//! tests per moving mover, O(n) per cycle for bounded density.

use crate::geometry::ConvexPolygon;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

type Key = (u32, i32, i32);

/// Multiplicative hash for small integer keys (deterministic, much cheaper than SipHash).
#[derive(Default)]
pub(crate) struct CellHasher(u64);

impl Hasher for CellHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.write_u64(*b as u64);
        }
    }
    fn write_u32(&mut self, i: u32) {
        self.write_u64(i as u64);
    }
    fn write_i32(&mut self, i: i32) {
        self.write_u64(i as u32 as u64);
    }
    fn write_u64(&mut self, i: u64) {
        self.0 = (self.0.rotate_left(5) ^ i).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
}

/// Uniform grid of envelope ids per coordinate system; reused every cycle (no allocation in
/// steady state).
#[derive(Debug, Default)]
pub(crate) struct Grid {
    cell: f64,
    map: HashMap<Key, Vec<u32>, BuildHasherDefault<CellHasher>>,
    used: Vec<Key>,
}

impl Grid {
    pub fn new(cell: f64) -> Self {
        Grid {
            cell: cell.max(1.0),
            map: HashMap::default(),
            used: Vec::new(),
        }
    }

    pub fn clear(&mut self) {
        for k in self.used.drain(..) {
            if let Some(v) = self.map.get_mut(&k) {
                v.clear();
            }
        }
        if self.map.len() > 4096 {
            self.map.retain(|_, v| !v.is_empty());
        }
    }

    fn range(&self, poly: &ConvexPolygon) -> (i32, i32, i32, i32) {
        let (lo, hi) = poly.aabb();
        let f = |v: f64| (v / self.cell).floor().clamp(-1e9, 1e9) as i32;
        (f(lo.x), f(hi.x), f(lo.y), f(hi.y))
    }

    pub fn insert(&mut self, cs: u32, id: u32, poly: &ConvexPolygon) {
        let (x0, x1, y0, y1) = self.range(poly);
        for ix in x0..=x1 {
            for iy in y0..=y1 {
                let v = self.map.entry((cs, ix, iy)).or_default();
                if v.is_empty() {
                    self.used.push((cs, ix, iy));
                }
                v.push(id);
            }
        }
    }

    /// Ids whose cells meet `poly`'s box (may contain duplicates; sorted and deduplicated).
    pub fn query(&self, cs: u32, poly: &ConvexPolygon, out: &mut Vec<u32>) {
        out.clear();
        let (x0, x1, y0, y1) = self.range(poly);
        for ix in x0..=x1 {
            for iy in y0..=y1 {
                if let Some(v) = self.map.get(&(cs, ix, iy)) {
                    out.extend_from_slice(v);
                }
            }
        }
        out.sort_unstable();
        out.dedup();
    }
}
