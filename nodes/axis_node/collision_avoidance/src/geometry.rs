//! Rail geometry, mover templates, parts and tracks (collision_avoidance.md §3.4) and the
//! position transformation of MC_TransformPosition (§5.9).

use super::errors as err;
use motion_core::{ErrorId, Rejection};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// A mover template: one perpendicular offset of the tool-centre path (§1.13).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MoverTemplate {
    /// Object id (≠ 0).
    pub oid: u32,
    /// Offset outward from the motor path \[mm\] (≥ 0).
    pub y_shift: f64,
    /// Usable by MC_RegisterCompensation / MC_TransformPosition.
    #[serde(default = "yes")]
    pub active: bool,
}

fn yes() -> bool {
    true
}

/// A part: the half-open interval `[start, start + length)` of the rail (modulo L on a ring).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Part {
    /// Object id (≠ 0).
    pub oid: u32,
    /// Start on the rail \[mm\].
    pub start: f64,
    /// Length \[mm\] (> 0).
    pub length: f64,
}

/// A track: an ordered list of adjacent parts; its origin is the start of its first part.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Track {
    /// Object id (≠ 0).
    pub oid: u32,
    /// Part ids in order.
    pub parts: Vec<u32>,
}

/// The "XTS Standard Object" of a CA group (§3.4); `Default`: the spec's example layout
/// without templates, parts or tracks.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CaGeometry {
    /// Zero shift of the origin \[mm\].
    pub rail_offset: f64,
    /// Motor-path length of one 180° curve \[mm\] (R = C/π).
    pub curve_arc_length: f64,
    /// Mover templates.
    pub mover_templates: Vec<MoverTemplate>,
    /// Parts.
    pub parts: Vec<Part>,
    /// Tracks.
    pub tracks: Vec<Track>,
}

impl Default for CaGeometry {
    fn default() -> Self {
        CaGeometry {
            rail_offset: 0.0,
            curve_arc_length: 500.0,
            mover_templates: Vec::new(),
            parts: Vec::new(),
            tracks: Vec::new(),
        }
    }
}

fn bad(group: &str, what: String) -> Rejection {
    Rejection::new(
        ErrorId::VALUE_OUT_OF_RANGE,
        format!("CA group '{group}': {what}"),
    )
}

impl CaGeometry {
    /// Startup validation against the rail length.
    pub fn validate(&self, group: &str, rail_length: f64) -> Result<(), Rejection> {
        let c = self.curve_arc_length;
        if !(c.is_finite()
            && c >= 0.0
            && rail_length - 2.0 * c >= 0.0
            && self.rail_offset.is_finite())
        {
            return Err(bad(
                group,
                format!("curve_arc_length = {c} does not fit the rail"),
            ));
        }
        for t in &self.mover_templates {
            if t.oid == 0 || !(t.y_shift.is_finite() && t.y_shift >= 0.0) {
                return Err(bad(
                    group,
                    format!("mover template {:#x}: y_shift = {}", t.oid, t.y_shift),
                ));
            }
        }
        for p in &self.parts {
            if p.oid == 0 || !(p.start.is_finite() && p.length.is_finite() && p.length > 0.0) {
                return Err(bad(group, format!("part {:#x} is invalid", p.oid)));
            }
        }
        for t in &self.tracks {
            if t.oid == 0 || t.parts.is_empty() || t.parts.iter().any(|id| self.part(*id).is_none())
            {
                return Err(bad(
                    group,
                    format!("track {:#x} names unknown parts", t.oid),
                ));
            }
        }
        Ok(())
    }

    /// A part by id.
    pub fn part(&self, oid: u32) -> Option<&Part> {
        self.parts.iter().find(|p| p.oid == oid)
    }

    /// A track by id.
    pub fn track(&self, oid: u32) -> Option<&Track> {
        self.tracks.iter().find(|t| t.oid == oid)
    }

    /// The part containing rail position `u` (modulo `l` on a ring).
    pub fn part_at(&self, x: f64, l: f64, ring: bool) -> Option<&Part> {
        self.parts.iter().find(|p| {
            let d = if ring {
                (x - p.start).rem_euclid(l)
            } else {
                x - p.start
            };
            (0.0..p.length).contains(&d)
        })
    }

    /// An *active* template's y-shift (`oid` 0 = motor path, shift 0).
    pub fn y_shift(&self, oid: u32) -> Result<f64, Rejection> {
        if oid == 0 {
            return Ok(0.0);
        }
        match self.mover_templates.iter().find(|t| t.oid == oid) {
            Some(t) if t.active => Ok(t.y_shift),
            _ => Err(Rejection::new(
                err::COMPENSATION_ERROR,
                format!("mover template {oid:#x} is unknown or inactive"),
            )),
        }
    }

    /// The offset path of a template with shift `y` on a rail of length `l`.
    pub fn path(&self, l: f64, y: f64) -> OffsetPath {
        OffsetPath {
            rail_length: l,
            curve_arc_length: self.curve_arc_length,
            rail_offset: self.rail_offset,
            y_shift: y,
        }
    }

    /// Motor coordinate `x` → offset-path coordinate of a template with shift `y` (§5.9).
    pub fn to_offset(&self, l: f64, y: f64, x: f64) -> f64 {
        self.path(l, y).to_offset(x)
    }

    /// Offset-path coordinate `s` (shift `y`) → motor coordinate (inverse of `to_offset`).
    pub fn from_offset(&self, l: f64, y: f64, s: f64) -> f64 {
        self.path(l, y).from_offset(s)
    }

    /// MC_TransformPosition (§5.9): `origin` → `destination` coordinate (OID 0 = motor path).
    pub fn transform(
        &self,
        l: f64,
        origin: u32,
        destination: u32,
        x: f64,
    ) -> Result<f64, Rejection> {
        let yo = self.y_shift(origin)?;
        let yd = self.y_shift(destination)?;
        // Via the motor coordinate.
        let motor = if origin == 0 {
            x
        } else {
            self.from_offset(l, yo, x)
        };
        Ok(if destination == 0 {
            motor
        } else {
            self.to_offset(l, yd, motor)
        })
    }
}

/// One offset (tool-centre) path of the starter-kit layout (§3.4, §5.9): plain numbers, `Copy`,
/// so a command can carry it. No alloc.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OffsetPath {
    /// Rail length L \[mm\].
    pub rail_length: f64,
    /// Motor-path length C of one 180° curve \[mm\].
    pub curve_arc_length: f64,
    /// Zero shift \[mm\].
    pub rail_offset: f64,
    /// Template y-shift \[mm\].
    pub y_shift: f64,
}

impl OffsetPath {
    /// Offset-path length of one lap \[mm\].
    fn lap(&self) -> f64 {
        self.rail_length + 2.0 * PI * self.y_shift
    }

    /// `Σ_y(u)`: offset arclength at motor arclength `u` from the fixed origin, periodic with
    /// one offset lap per rail lap.
    fn sigma(&self, u: f64) -> f64 {
        let (l, c, y) = (self.rail_length, self.curve_arc_length, self.y_shift);
        let k = (u / l).floor();
        let r = u - k * l;
        let ls = (l - 2.0 * c) / 2.0;
        let theta = if r < ls {
            0.0
        } else if r < ls + c {
            PI * (r - ls) / c
        } else if r < 2.0 * ls + c {
            PI
        } else {
            PI + PI * (r - 2.0 * ls - c) / c
        };
        k * self.lap() + r + y * theta
    }

    /// Inverse of `sigma` (piecewise linear).
    fn sigma_inv(&self, s: f64) -> f64 {
        let (l, c, y) = (self.rail_length, self.curve_arc_length, self.y_shift);
        let lt = self.lap();
        let k = (s / lt).floor();
        let r = s - k * lt;
        let ls = (l - 2.0 * c) / 2.0;
        let slope = if c > 0.0 { (c + PI * y) / c } else { 1.0 };
        let curve = c + PI * y;
        let u = if r < ls {
            r
        } else if r < ls + curve {
            ls + (r - ls) / slope
        } else if r < 2.0 * ls + curve {
            r - PI * y
        } else {
            2.0 * ls + c + (r - 2.0 * ls - curve) / slope
        };
        k * l + u
    }

    /// dΣ/dx at motor position `x`: 1 on the straights, (C + πy)/C in the curves.
    pub fn slope(&self, x: f64) -> f64 {
        let (l, c) = (self.rail_length, self.curve_arc_length);
        let r = (x + self.rail_offset).rem_euclid(l);
        let ls = (l - 2.0 * c) / 2.0;
        let curve = (ls..ls + c).contains(&r) || r >= 2.0 * ls + c;
        if curve && c > 0.0 {
            (c + PI * self.y_shift) / c
        } else {
            1.0
        }
    }

    /// Motor coordinate → offset-path coordinate (same physical zero).
    pub fn to_offset(&self, x: f64) -> f64 {
        let off = self.rail_offset;
        self.sigma(x + off) - self.sigma(off)
    }

    /// Offset-path coordinate → motor coordinate.
    pub fn from_offset(&self, s: f64) -> f64 {
        let off = self.rail_offset;
        self.sigma_inv(s + self.sigma(off)) - off
    }
}
