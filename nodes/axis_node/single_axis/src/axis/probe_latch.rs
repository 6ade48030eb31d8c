//! Latching of the armed touch probes (§4.5) each cycle. The latch data are in
//! [`crate::probe`].

use super::Axis;
use crate::handshake::Handshake;
use crate::inputs::{SignalEdge, TouchProbeMode};
use crate::modulo::modulo;
use crate::probe::*;

impl Axis {
    fn in_window(&self, p: &Probe, pos: f64) -> bool {
        if !p.window_only {
            return true;
        }
        if p.modulo_positions {
            let m = modulo(pos, self.cfg.modulo_value);
            if p.first <= p.last {
                m >= p.first && m <= p.last
            } else {
                // Window across the period end.
                m >= p.first || m <= p.last
            }
        } else {
            pos >= p.first && pos <= p.last
        }
    }

    /// Candidate edge positions of slot `k` in this cycle (at most the first two).
    fn probe_edges(&self, k: usize, p: &Probe, prev_raw: f64, out: &mut [f64; 4]) -> usize {
        let mut n = 0;
        let raw = self.act_pos - self.coord_offset;
        if k < 2 {
            // Client-driven level.
            let (prev, now) = (self.probe_prev[k], self.probe_level[k]);
            let hit = match p.edge {
                SignalEdge::RisingEdge => !prev && now,
                SignalEdge::FallingEdge => prev && !now,
            };
            if hit {
                out[n] = self.act_pos;
                n += 1;
            }
            if p.edge == SignalEdge::RisingEdge {
                let marks = if k == 0 {
                    &self.cfg.probe_marks
                } else {
                    &self.cfg.probe_marks_2
                };
                for &m in marks {
                    let crossed =
                        (m - prev_raw) * (raw - m) >= 0.0 && raw != prev_raw && m != prev_raw;
                    if crossed && n < out.len() {
                        out[n] = self.act_pos - (raw - m);
                        n += 1;
                    }
                }
            }
        } else if p.plc_event && !p.plc_prev {
            out[n] = self.act_pos;
            n += 1;
        }
        // Earliest crossing first (in the direction of travel).
        let dir = if raw >= prev_raw { 1.0 } else { -1.0 };
        out[..n].sort_by(|a, b| (a * dir).total_cmp(&(b * dir)));
        n
    }

    /// One cycle of all armed latches (after the actual values).
    pub fn probe_step(&mut self, prev_raw: f64, fbs: &mut Handshake) {
        for k in 0..3 {
            let Some(mut p) = self.probes[k] else {
                continue;
            };
            let mut edges = [0.0; 4];
            let n = self.probe_edges(k, &p, prev_raw, &mut edges);
            p.plc_prev = p.plc_event;
            let mut accepted = 0;
            let mut first = None;
            for &e in &edges[..n] {
                if self.in_window(&p, e) {
                    accepted += 1;
                    first.get_or_insert(e);
                }
                // Outside the window: discarded, the latch stays armed.
            }
            if let Some(pos) = first {
                let m = modulo(pos, self.cfg.modulo_value);
                let out = ProbeOutputs {
                    recorded_position: if p.modulo_positions { m } else { pos },
                    counter: accepted as f64,
                    absolute_position: pos,
                    modulo_position: m,
                    edge_cycle: fbs.cycle,
                };
                fbs.probes.insert(p.owner, out);
                if p.mode != TouchProbeMode::Continous {
                    fbs.done(p.owner);
                    self.probes[k] = None;
                    continue;
                }
            }
            self.probes[k] = Some(p);
        }
        self.probe_prev = self.probe_level;
    }
}
