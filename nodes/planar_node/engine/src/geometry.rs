//! Plane geometry of footprints and swept areas (xplanar.md §5.11).
//!
//! Every area is a small convex polygon in a fixed-size array (no allocation on the cycle
//! path). Overlap uses the separating-axis test on closed sets with tolerance
//! [`TOUCH_TOLERANCE`]: touching edges are not a collision (§5.11).

use nalgebra::Vector2;

/// 2-D vector \[mm\].
pub type V2 = Vector2<f64>;

/// Overlap below this depth counts as touching, not colliding \[mm\] (§5.11).
pub const TOUCH_TOLERANCE: f64 = 1e-6;

/// Side of one stator tile \[mm\] (§0).
pub const STATOR_SIDE: f64 = 240.0;

const MAX_VERTS: usize = 16;

/// A convex polygon with at most 16 vertices, counter-clockwise.
#[derive(Clone, Copy, Debug)]
pub struct ConvexPolygon {
    pts: [V2; MAX_VERTS],
    n: usize,
}

impl ConvexPolygon {
    /// The vertices.
    pub fn vertices(&self) -> &[V2] {
        &self.pts[..self.n]
    }

    /// Rectangle `w × h` centred at `center`, rotated by `c_deg` (the mover footprint).
    pub fn rect(center: V2, w: f64, h: f64, c_deg: f64) -> Self {
        let (s, c) = c_deg.to_radians().sin_cos();
        let ex = V2::new(c, s) * (w / 2.0);
        let ey = V2::new(-s, c) * (h / 2.0);
        ConvexPolygon::from_ccw(&[
            center - ex - ey,
            center + ex - ey,
            center + ex + ey,
            center - ex + ey,
        ])
    }

    /// The polygon moved by `d`.
    pub fn translated(&self, d: V2) -> Self {
        let mut q = *self;
        q.pts[..q.n].iter_mut().for_each(|p| *p += d);
        q
    }

    /// Axis-aligned box.
    pub fn aabb_box(min: V2, max: V2) -> Self {
        ConvexPolygon::from_ccw(&[min, V2::new(max.x, min.y), max, V2::new(min.x, max.y)])
    }

    fn from_ccw(p: &[V2]) -> Self {
        let mut pts = [V2::zeros(); MAX_VERTS];
        pts[..p.len()].copy_from_slice(p);
        ConvexPolygon { pts, n: p.len() }
    }

    /// Convex hull of up to 16 points (Andrew's monotone chain).
    pub fn hull(points: &[V2]) -> Self {
        debug_assert!(!points.is_empty() && points.len() <= MAX_VERTS);
        let mut p = [V2::zeros(); MAX_VERTS];
        let m = points.len().min(MAX_VERTS);
        p[..m].copy_from_slice(&points[..m]);
        let p = &mut p[..m];
        p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
        let cross = |o: V2, a: V2, b: V2| (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
        let mut h = [V2::zeros(); 2 * MAX_VERTS];
        let mut k = 0usize;
        for &q in p.iter() {
            while k >= 2 && cross(h[k - 2], h[k - 1], q) <= 1e-12 {
                k -= 1;
            }
            h[k] = q;
            k += 1;
        }
        let lower = k + 1;
        for &q in p.iter().rev().skip(1) {
            while k >= lower && cross(h[k - 2], h[k - 1], q) <= 1e-12 {
                k -= 1;
            }
            h[k] = q;
            k += 1;
        }
        let n = if k > 1 { k - 1 } else { k };
        let mut pts = [V2::zeros(); MAX_VERTS];
        let n = n.min(MAX_VERTS);
        pts[..n].copy_from_slice(&h[..n]);
        ConvexPolygon { pts, n }
    }

    /// Convex hull of two polygons (the exact swept area of a translation without rotation).
    pub fn hull_of(a: &ConvexPolygon, b: &ConvexPolygon) -> Self {
        let mut pts = [V2::zeros(); MAX_VERTS];
        let mut m = 0;
        for p in a.vertices().iter().chain(b.vertices()) {
            if m < MAX_VERTS {
                pts[m] = *p;
                m += 1;
            }
        }
        ConvexPolygon::hull(&pts[..m])
    }

    /// Minkowski sum of this polygon (≤ 4 vertices) and `other` (≤ 4 vertices).
    pub fn minkowski(&self, other: &ConvexPolygon) -> Self {
        let mut pts = [V2::zeros(); MAX_VERTS];
        let mut m = 0;
        for a in self.vertices() {
            for b in other.vertices() {
                if m < MAX_VERTS {
                    pts[m] = a + b;
                    m += 1;
                }
            }
        }
        ConvexPolygon::hull(&pts[..m])
    }

    /// Axis-aligned bounding box (min, max).
    pub fn aabb(&self) -> (V2, V2) {
        let mut lo = V2::new(f64::INFINITY, f64::INFINITY);
        let mut hi = V2::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
        for p in self.vertices() {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        (lo, hi)
    }

    fn project(&self, axis: V2) -> (f64, f64) {
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for p in self.vertices() {
            let d = p.dot(&axis);
            lo = lo.min(d);
            hi = hi.max(d);
        }
        (lo, hi)
    }

    fn separated_by_edges_of(&self, other: &ConvexPolygon, tol: f64) -> bool {
        let n = self.n;
        for i in 0..n {
            let e = self.pts[(i + 1) % n] - self.pts[i];
            let len = e.norm();
            if len < 1e-12 {
                continue;
            }
            let axis = V2::new(-e.y, e.x) / len;
            let (a0, a1) = self.project(axis);
            let (b0, b1) = other.project(axis);
            if a1 <= b0 + tol || b1 <= a0 + tol {
                return true;
            }
        }
        false
    }

    /// True if the interiors overlap by more than [`TOUCH_TOLERANCE`].
    pub fn intersects(&self, other: &ConvexPolygon) -> bool {
        let (alo, ahi) = self.aabb();
        let (blo, bhi) = other.aabb();
        let t = TOUCH_TOLERANCE;
        if ahi.x <= blo.x + t || bhi.x <= alo.x + t || ahi.y <= blo.y + t || bhi.y <= alo.y + t {
            return false;
        }
        !(self.separated_by_edges_of(other, t) || other.separated_by_edges_of(self, t))
    }

    /// True if the polygon lies inside the union of the square tiles (lower-left corners,
    /// side [`STATOR_SIDE`]), up to [`TOUCH_TOLERANCE`].
    ///
    /// The bounding box is cut into cells at every tile edge; a cell whose centre is not on a
    /// tile is outside, and the polygon must not overlap any outside cell.
    pub fn inside_tiles(&self, tiles: &[V2]) -> bool {
        let (lo, hi) = self.aabb();
        let mut xs: Vec<f64> = vec![lo.x, hi.x];
        let mut ys: Vec<f64> = vec![lo.y, hi.y];
        for t in tiles {
            for x in [t.x, t.x + STATOR_SIDE] {
                if x > lo.x && x < hi.x {
                    xs.push(x);
                }
            }
            for y in [t.y, t.y + STATOR_SIDE] {
                if y > lo.y && y < hi.y {
                    ys.push(y);
                }
            }
        }
        xs.sort_by(f64::total_cmp);
        ys.sort_by(f64::total_cmp);
        for i in 0..xs.len() - 1 {
            if xs[i + 1] - xs[i] <= TOUCH_TOLERANCE {
                continue;
            }
            for j in 0..ys.len() - 1 {
                if ys[j + 1] - ys[j] <= TOUCH_TOLERANCE {
                    continue;
                }
                let mid = V2::new((xs[i] + xs[i + 1]) / 2.0, (ys[j] + ys[j + 1]) / 2.0);
                if tile_containing(tiles, mid).is_none() {
                    let cell = ConvexPolygon::aabb_box(
                        V2::new(xs[i], ys[j]),
                        V2::new(xs[i + 1], ys[j + 1]),
                    );
                    if self.intersects(&cell) {
                        return false;
                    }
                }
            }
        }
        true
    }
}

/// Index of the tile (lower-left corners) containing `p` (closed squares).
pub fn tile_containing(tiles: &[V2], p: V2) -> Option<usize> {
    tiles.iter().position(|t| {
        p.x >= t.x - 1e-9
            && p.x <= t.x + STATOR_SIDE + 1e-9
            && p.y >= t.y - 1e-9
            && p.y <= t.y + STATOR_SIDE + 1e-9
    })
}

/// Number of exposed 240 mm stator edges of a tile set (boundary elements, §1.2 proposal).
pub fn boundary_elements(tiles: &[V2]) -> usize {
    let has = |p: V2| {
        tiles
            .iter()
            .any(|t| (t.x - p.x).abs() < 1e-6 && (t.y - p.y).abs() < 1e-6)
    };
    let s = STATOR_SIDE;
    tiles
        .iter()
        .map(|t| {
            [
                V2::new(-s, 0.0),
                V2::new(s, 0.0),
                V2::new(0.0, -s),
                V2::new(0.0, s),
            ]
            .iter()
            .filter(|d| !has(t + *d))
            .count()
        })
        .sum()
}

/// True if two tiles overlap (more than touching).
pub fn tiles_overlap(a: V2, b: V2) -> bool {
    (a.x - b.x).abs() < STATOR_SIDE - 1e-6 && (a.y - b.y).abs() < STATOR_SIDE - 1e-6
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn touching_rectangles_do_not_intersect() {
        let a = ConvexPolygon::rect(V2::new(0.0, 0.0), 155.0, 155.0, 0.0);
        let b = ConvexPolygon::rect(V2::new(155.0, 0.0), 155.0, 155.0, 0.0);
        assert!(!a.intersects(&b));
        let c = ConvexPolygon::rect(V2::new(154.9, 0.0), 155.0, 155.0, 0.0);
        assert!(a.intersects(&c));
    }

    #[test]
    fn rotated_rectangle_needs_sat() {
        // A 45° square reaches 109.6 mm from its centre along x.
        let a = ConvexPolygon::rect(V2::new(0.0, 0.0), 155.0, 155.0, 45.0);
        let b = ConvexPolygon::rect(V2::new(186.0, 0.0), 155.0, 155.0, 0.0);
        assert!(a.intersects(&b));
        let b = ConvexPolygon::rect(V2::new(188.0, 0.0), 155.0, 155.0, 0.0);
        assert!(!a.intersects(&b));
        // Diagonal neighbours whose boxes overlap but the rotated square does not reach.
        let d = ConvexPolygon::rect(V2::new(150.0, 150.0), 155.0, 155.0, 0.0);
        let e = ConvexPolygon::rect(V2::new(0.0, 0.0), 155.0, 155.0, 45.0);
        assert!(!e.intersects(&d));
    }

    #[test]
    fn hull_of_sweep_is_exact() {
        let a = ConvexPolygon::rect(V2::new(0.0, 0.0), 2.0, 2.0, 0.0);
        let b = ConvexPolygon::rect(V2::new(10.0, 10.0), 2.0, 2.0, 0.0);
        let h = ConvexPolygon::hull_of(&a, &b);
        assert_eq!(h.vertices().len(), 6);
        // A point beside the diagonal band is outside.
        let probe = ConvexPolygon::rect(V2::new(8.0, 1.0), 0.5, 0.5, 0.0);
        assert!(!h.intersects(&probe));
        let probe = ConvexPolygon::rect(V2::new(5.0, 5.0), 0.5, 0.5, 0.0);
        assert!(h.intersects(&probe));
    }

    #[test]
    fn containment_in_tiles() {
        let tiles = [V2::new(0.0, 0.0), V2::new(240.0, 0.0)];
        assert!(ConvexPolygon::rect(V2::new(240.0, 120.0), 155.0, 155.0, 0.0).inside_tiles(&tiles));
        assert!(
            !ConvexPolygon::rect(V2::new(420.0, 120.0), 155.0, 155.0, 0.0).inside_tiles(&tiles)
        );
        let l = [V2::new(0.0, 0.0), V2::new(240.0, 0.0), V2::new(0.0, 240.0)];
        // Over the missing upper-right tile of an L.
        assert!(!ConvexPolygon::rect(V2::new(240.0, 240.0), 100.0, 100.0, 0.0).inside_tiles(&l));
        assert_eq!(boundary_elements(&l), 8);
        let sq = [
            V2::new(0.0, 0.0),
            V2::new(240.0, 0.0),
            V2::new(0.0, 240.0),
            V2::new(240.0, 240.0),
        ];
        assert_eq!(boundary_elements(&sq), 8);
    }
}
