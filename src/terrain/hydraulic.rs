//! Hydraulic erosion by virtual pipes (Mei, Decaudin & Hu 2007, "Fast hydraulic erosion
//! simulation and visualization on GPU", Pacific Graphics 2007, §3): rain raises the water
//! on every point, water flows to the lattice neighbours through pipes whose flux grows
//! with the difference of the water surfaces (eq. 2–5, the flux scaled down where it would
//! take more than `MAX_OUTFLOW_SHARE` of the point's water), the flow's speed and the
//! terrain's tilt give the sediment capacity C = Kc·sin α·|v| (eq. 8), the terrain
//! dissolves into the water where the water carries less than C and deposits where it
//! carries more (eq. 9–10), the sediment moves with the water, and the water evaporates
//! (eq. 11).
//!
//! Three departures: a point loses at most a quarter of its water per iteration
//! (`MAX_OUTFLOW_SHARE`, for stability), and two for tiles to equal the whole grid bit for
//! bit and for mass to be accounted for:
//! - Sediment moves with the water through the pipes (the share of a point's water leaving
//!   through each pipe takes that share of its sediment), not by Mei's semi-Lagrangian
//!   back-tracing, whose reach grows with the speed and which creates and destroys mass.
//!   So the terrain plus the suspended sediment keeps its volume up to rounding, and each
//!   iteration reaches two points: the new state of a point is a function of the old
//!   states within two lattice steps (the pipes' flux from one step, the water and
//!   sediment each point receives from its neighbours' new flux). A rectangle grown by a
//!   halo of two points per iteration therefore gives its inner points exactly the whole
//!   grid's values (as for thermal erosion, `erosion.rs`).
//! - What is still suspended after the last iteration is deposited where it is, so the
//!   heights keep the terrain's volume.
//!
//! Pipes join each point to its edge neighbours (four on the square lattice, six on the
//! triangular one); no pipe leaves the grid (a closed basin). Lengths are world units;
//! g = 9.81.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::{Grid, Heightfield, TerrainParams};
use crate::error::{Error, Result};

/// Bytes per point of a run's state beyond its heights: water, sediment and six pipes'
/// flux, each twice (old and new), and the next heights.
pub const BYTES_PER_POINT: u64 = 8 * (2 * (2 + 6) + 1);

/// Bytes per point [`erode_with_layers`] takes beyond [`BYTES_PER_POINT`]: the heights
/// before the run, three sums over the iterations and the four layers.
pub const LAYER_BYTES_PER_POINT: u64 = 8 * (1 + 3 + 4);

/// The largest share of a point's water that leaves it in one iteration. Mei et al. scale
/// the outflow down only where it would take more than all of it (K = 1, eq. 5); with the
/// sediment moving with the water, a point then empties into its neighbours each step and
/// the dissolving and deposition alternate from point to point: on a 513² terrain (H 1,
/// σ 2), 50 iterations raised the RMS of the heights' Laplacian 0.0045 → 0.0210 and of the
/// gradient 0.0152 → 0.0345 (a hatching a point wide in every picture). With a quarter,
/// the same run smooths (0.0036, 0.0131) as erosion does; a half still roughens (0.0055).
const MAX_OUTFLOW_SHARE: f64 = 0.25;

/// Gravity in the pipes' flux (eq. 3).
const GRAVITY: f64 = 9.81;
/// The smallest sin α the capacity uses: flat ground still carries sediment where water
/// runs over it (Mei et al. §3.3 note the same lower bound).
const MIN_TILT: f64 = 0.05;

/// Hydraulic erosion's parameters (Mei et al. 2007's constants).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct HydraulicErosion {
    /// Iterations; the halo a tile needs is two points per iteration.
    pub iterations: u32,
    /// Rain Kr: water depth added to every point per unit time (world height units).
    pub rain: f64,
    /// Evaporation Ke: the share of the water that evaporates per unit time.
    pub evaporation: f64,
    /// Sediment capacity Kc (eq. 8).
    pub capacity: f64,
    /// Dissolving rate Ks: the share of the missing capacity dissolved per iteration.
    pub dissolving: f64,
    /// Deposition rate Kd: the share of the excess sediment deposited per iteration.
    pub deposition: f64,
    /// Time step Δt.
    pub time_step: f64,
}

impl Default for HydraulicErosion {
    fn default() -> Self {
        HydraulicErosion {
            iterations: 50,
            rain: 0.01,
            evaporation: 0.5,
            capacity: 1.0,
            dissolving: 0.3,
            deposition: 0.3,
            time_step: 0.05,
        }
    }
}

impl HydraulicErosion {
    /// Checks every parameter's range.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the parameter (by its command-line flag).
    pub fn validate(&self) -> Result<()> {
        let finite = |name: &str, v: f64| {
            if v.is_finite() {
                Ok(())
            } else {
                Err(Error::InvalidInput(format!("--{name} {v} must be a finite number")))
            }
        };
        for (name, v) in [
            ("rain", self.rain),
            ("evaporation", self.evaporation),
            ("capacity", self.capacity),
            ("dissolving", self.dissolving),
            ("deposition", self.deposition),
            ("time-step", self.time_step),
        ] {
            finite(name, v)?;
        }
        let refuse = |text: String| Err(Error::InvalidInput(text));
        if !(self.time_step > 0.0 && self.time_step <= 1.0) {
            return refuse(format!("--time-step {} must lie in (0, 1]", self.time_step));
        }
        if self.rain <= 0.0 {
            return refuse(format!("--rain {} must be positive (water depth per unit time)", self.rain));
        }
        if !(self.evaporation >= 0.0 && self.evaporation * self.time_step < 1.0) {
            return refuse(format!(
                "--evaporation {} must be at least 0 and below 1 / --time-step ({}): the share evaporated per step",
                self.evaporation,
                1.0 / self.time_step
            ));
        }
        if self.capacity <= 0.0 {
            return refuse(format!("--capacity {} must be positive", self.capacity));
        }
        for (name, v) in [("dissolving", self.dissolving), ("deposition", self.deposition)] {
            if !(v > 0.0 && v <= 1.0) {
                return refuse(format!("--{name} {v} must lie in (0, 1]: a share per iteration"));
            }
        }
        Ok(())
    }

    /// The halo a region needs: two points per iteration.
    pub fn halo(&self) -> u64 {
        2 * u64::from(self.iterations)
    }
}

/// One pipe: the neighbour's offset, the pipe's length and its unit direction in the world.
#[derive(Debug, Clone, Copy)]
struct Pipe {
    dx: i64,
    dy: i64,
    length: f64,
    direction: [f64; 2],
}

/// The pipes of the terrain's lattice and the area each point stands for.
fn pipes(params: &TerrainParams) -> (Vec<Pipe>, f64) {
    let last = (params.size - 1) as f64;
    match params.grid {
        Grid::Square => {
            let (sx, sy) = (params.width / last, params.depth / last);
            let pipe = |dx: i64, dy: i64, length: f64| Pipe { dx, dy, length, direction: [dx as f64, dy as f64] };
            (vec![pipe(-1, 0, sx), pipe(1, 0, sx), pipe(0, -1, sy), pipe(0, 1, sy)], sx * sy)
        }
        Grid::Triangle | Grid::Hex => {
            // Row j is offset by half a step per row: neighbour (dx, dy) lies at
            // (dx + dy/2, dy·√3/2) steps.
            let s = params.width / last;
            let h = 3f64.sqrt() / 2.0;
            let pipes = [(0, -1), (1, -1), (-1, 0), (1, 0), (-1, 1), (0, 1)]
                .into_iter()
                .map(|(dx, dy): (i64, i64)| {
                    let (wx, wy) = (dx as f64 + dy as f64 / 2.0, dy as f64 * h);
                    let norm = wx.hypot(wy);
                    Pipe { dx, dy, length: s, direction: [wx / norm, wy / norm] }
                })
                .collect();
            (pipes, s * s * h)
        }
    }
}

/// What an erosion run moved, for the accounting of mass (world volumes).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct HydraulicBudget {
    /// Water that fell as rain.
    pub rained: f64,
    /// Water that evaporated.
    pub evaporated: f64,
    /// Water still standing after the last iteration.
    pub water_left: f64,
    /// Sediment deposited where it was after the last iteration.
    pub sediment_settled: f64,
}

/// The state of every point of a rectangle.
struct State {
    water: Vec<f64>,
    sediment: Vec<f64>,
    /// Outflow through each pipe, `pipes.len()` per point.
    flux: Vec<f64>,
}

/// Erodes `field` in place for `erosion.iterations` iterations. As for thermal erosion,
/// the points of `field.rect` see no neighbour outside it: only points at least
/// [`HydraulicErosion::halo`] inside the rectangle (or on the grid's border) are what the
/// whole grid gives. Returns the water and sediment accounting (volumes over the
/// rectangle).
pub fn erode(field: &mut Heightfield, params: &TerrainParams, erosion: &HydraulicErosion) -> HydraulicBudget {
    run(field, params, erosion, None)
}

/// [`erode`], also returning the [`ErosionLayers`] of the run on the same rectangle (the
/// same heights bit for bit; like them, only points at least the halo inside the rectangle
/// are what the whole grid gives).
pub fn erode_with_layers(
    field: &mut Heightfield,
    params: &TerrainParams,
    erosion: &HydraulicErosion,
) -> (HydraulicBudget, ErosionLayers) {
    let before = field.heights.clone();
    let n = before.len();
    let mut sums = Sums { outflow: vec![0.0; n], water: vec![0.0; n], standing: Vec::new() };
    let budget = run(field, params, erosion, Some(&mut sums));
    let layers = ErosionLayers::of(erosion, &before, &field.heights, &sums);
    (budget, layers)
}

/// The flow layer's reference, in points' rain: 0.5 where this many points' rain ran through.
const FLOW_REFERENCE: f64 = 10.0;

/// What the layers sum over the iterations, per point.
struct Sums {
    /// Water that ran across the point (its net flow's volume), as a depth over its area.
    outflow: Vec<f64>,
    /// The point's water depth after each iteration.
    water: Vec<f64>,
    /// The water standing after the last iteration.
    standing: Vec<f64>,
}

/// The layers terrain artists export beside the eroded heights, each a mask in [0, 1] of
/// the run on one rectangle (row-major, as the heights). Each is x / (x + reference), so it
/// is 0.5 where the quantity equals a reference set by the parameters alone, never by the
/// rectangle (tiles agree bit for bit):
/// - `flow`: the water that ran across the point over the run (its net flow through the
///   pipes, the flux in less the flux back, as in eq. 7), against ten times the rain that
///   fell on it (Kr·Δt·iterations): 0.5 where ten points' rain ran through, rivers and
///   gullies near 1;
/// - `water`: the water standing after the last iteration, against the depth of flat
///   ground where rain and evaporation balance (Kr/Ke; the rain fallen where Ke = 0): lakes;
/// - `wetness`: the water depth averaged over the iterations, against the same depth;
/// - `sediment`: the deposit (heights raised by the run), against what water of that depth
///   carries at the capacity Kc: fans and valley floors.
#[derive(Debug, Clone, PartialEq)]
pub struct ErosionLayers {
    /// Water that ran through each point.
    pub flow: Vec<f64>,
    /// Standing water after the run.
    pub water: Vec<f64>,
    /// Water depth over the run.
    pub wetness: Vec<f64>,
    /// Deposited sediment.
    pub sediment: Vec<f64>,
}

impl ErosionLayers {
    fn of(erosion: &HydraulicErosion, before: &[f64], after: &[f64], sums: &Sums) -> Self {
        let iterations = f64::from(erosion.iterations.max(1));
        let rain_fallen = erosion.rain * erosion.time_step * iterations;
        let balanced = if erosion.evaporation > 0.0 { erosion.rain / erosion.evaporation } else { rain_fallen };
        let carried = erosion.capacity * balanced;
        let mask = |x: f64, reference: f64| {
            let x = x.max(0.0);
            if x + reference > 0.0 { x / (x + reference) } else { 0.0 }
        };
        ErosionLayers {
            flow: sums.outflow.par_iter().map(|&f| mask(f, FLOW_REFERENCE * rain_fallen)).collect(),
            water: sums.standing.par_iter().map(|&w| mask(w, balanced)).collect(),
            wetness: sums.water.par_iter().map(|&w| mask(w / iterations, balanced)).collect(),
            sediment: before.par_iter().zip(after).map(|(&b, &a)| mask(a - b, carried)).collect(),
        }
    }
}

/// The run behind [`erode`] and [`erode_with_layers`]: `sums`, where given, gathers what
/// the layers need after each iteration.
fn run(
    field: &mut Heightfield,
    params: &TerrainParams,
    erosion: &HydraulicErosion,
    mut sums: Option<&mut Sums>,
) -> HydraulicBudget {
    let (pipes, area) = pipes(params);
    let k = pipes.len();
    let (cols, rows) = (field.rect.width(), field.rect.height());
    let n = cols * rows;
    let dt = erosion.time_step;
    let neighbour = |i: usize, j: usize, p: &Pipe| {
        let (ni, nj) = (i as i64 + p.dx, j as i64 + p.dy);
        (ni >= 0 && nj >= 0 && (ni as usize) < cols && (nj as usize) < rows).then(|| nj as usize * cols + ni as usize)
    };
    // The pipe of a neighbour that points back (the opposite offset).
    let back: Vec<usize> = pipes
        .iter()
        .map(|p| pipes.iter().position(|q| q.dx == -p.dx && q.dy == -p.dy).expect("lattices are symmetric"))
        .collect();
    let mut state = State { water: vec![0.0; n], sediment: vec![0.0; n], flux: vec![0.0; n * k] };
    let mut next = State { water: vec![0.0; n], sediment: vec![0.0; n], flux: vec![0.0; n * k] };
    let mut terrain_next = vec![0.0; n];
    let mut budget = HydraulicBudget::default();
    let rain = erosion.rain * dt;
    for _ in 0..erosion.iterations {
        budget.rained += rain * area * n as f64;
        let b = &field.heights;
        let old = &state;
        // 1. Rain (eq. 1) and the pipes' new outflow (eq. 2–5): from the old state within
        //    one step.
        next.flux.par_chunks_mut(cols * k).enumerate().for_each(|(j, row)| {
            for i in 0..cols {
                let c = j * cols + i;
                let surface = b[c] + old.water[c] + rain;
                let out = &mut row[i * k..(i + 1) * k];
                let mut total = 0.0;
                for (slot, p) in pipes.iter().enumerate() {
                    out[slot] = match neighbour(i, j, p) {
                        Some(m) => {
                            let drop = surface - (b[m] + old.water[m] + rain);
                            (old.flux[c * k + slot] + dt * p.length * GRAVITY * drop).max(0.0)
                        }
                        None => 0.0,
                    };
                    total += out[slot];
                }
                let volume = MAX_OUTFLOW_SHARE * (old.water[c] + rain) * area;
                if total * dt > volume {
                    let scale = volume / (total * dt);
                    for f in out.iter_mut() {
                        *f *= scale;
                    }
                }
            }
        });
        let flux = &next.flux;
        // 2. Water and sediment move through the pipes (eq. 6, and the sediment with the
        //    water's shares), the flow's speed and the tilt set the capacity (eq. 7–8), the
        //    terrain dissolves or the sediment deposits (eq. 9–10), the water evaporates
        //    (eq. 11): from the new flux within one step, so the old state within two.
        let evaporated_per_row: Vec<f64> = next
            .water
            .par_chunks_mut(cols)
            .zip(next.sediment.par_chunks_mut(cols))
            .zip(terrain_next.par_chunks_mut(cols))
            .enumerate()
            .map(|(j, ((water, sediment), terrain))| {
                let mut evaporated = 0.0;
                for i in 0..cols {
                    let c = j * cols + i;
                    let before = old.water[c] + rain;
                    let leaving = |m: usize, slot: usize| flux[m * k + slot] * dt;
                    // The share of a point's water that leaves it through one pipe.
                    let share = |m: usize, slot: usize| {
                        let volume = (old.water[m] + rain) * area;
                        if volume > 0.0 { (leaving(m, slot) / volume).min(1.0) } else { 0.0 }
                    };
                    let (mut inflow, mut outflow) = (0.0, 0.0);
                    let (mut sediment_in, mut sediment_out) = (0.0, 0.0);
                    let mut net = [0.0f64; 2];
                    for (slot, p) in pipes.iter().enumerate() {
                        let out = leaving(c, slot);
                        outflow += out;
                        sediment_out += old.sediment[c] * share(c, slot);
                        let mut through = out;
                        if let Some(m) = neighbour(i, j, p) {
                            let came = leaving(m, back[slot]);
                            inflow += came;
                            sediment_in += old.sediment[m] * share(m, back[slot]);
                            through -= came;
                        }
                        net[0] += through * p.direction[0];
                        net[1] += through * p.direction[1];
                    }
                    let after = before + (inflow - outflow) / area;
                    let mut s = old.sediment[c] - sediment_out + sediment_in;
                    // Speed: the net flow per unit time through the point's width, over the
                    // mean depth (eq. 7).
                    let depth = 0.5 * (before + after);
                    let speed = if depth > 0.0 { 0.5 * net[0].hypot(net[1]) / dt / (area.sqrt() * depth) } else { 0.0 };
                    let (tilt, lowest, highest) = tilt_and_range(b, cols, rows, i, j, &pipes);
                    let tilt = tilt.max(MIN_TILT);
                    // At most Kc times the water's depth: where a film of water runs fast,
                    // eq. 8 alone dissolves without bound (the terrain grew spikes).
                    let capacity = erosion.capacity * (tilt * speed).min(after.max(0.0));
                    let mut height = b[c];
                    // Neither digs below the lowest neighbour nor heaps above the highest:
                    // unbounded, the two fed each other into spikes and pits a point wide.
                    if capacity > s {
                        let taken = (erosion.dissolving * (capacity - s)).min((height - lowest).max(0.0));
                        height -= taken;
                        s += taken;
                    } else {
                        let left = (erosion.deposition * (s - capacity)).min((highest - height).max(0.0));
                        height += left;
                        s -= left;
                    }
                    let gone = after * erosion.evaporation * dt;
                    evaporated += gone * area;
                    water[i] = after - gone;
                    sediment[i] = s;
                    terrain[i] = height;
                }
                evaporated
            })
            .collect();
        // Summed in row order: the same total at any thread count.
        budget.evaporated += evaporated_per_row.iter().sum::<f64>();
        std::mem::swap(&mut field.heights, &mut terrain_next);
        std::mem::swap(&mut state, &mut next);
        if let Some(sums) = sums.as_deref_mut() {
            let (flux, water) = (&state.flux, &state.water);
            sums.outflow.par_chunks_mut(cols).zip(sums.water.par_chunks_mut(cols)).enumerate().for_each(
                |(j, (out, wet))| {
                    for i in 0..cols {
                        let c = j * cols + i;
                        // The net flow through the point: out through each pipe less what
                        // comes back through it, along the pipe.
                        let mut net = [0.0f64; 2];
                        for (slot, p) in pipes.iter().enumerate() {
                            let back_in = neighbour(i, j, p).map_or(0.0, |m| flux[m * k + back[slot]]);
                            let through = flux[c * k + slot] - back_in;
                            net[0] += through * p.direction[0];
                            net[1] += through * p.direction[1];
                        }
                        out[i] += 0.5 * net[0].hypot(net[1]) * dt / area;
                        wet[i] += water[c];
                    }
                },
            );
        }
    }
    if let Some(sums) = sums {
        sums.standing = state.water.clone();
    }
    // What is still suspended settles where it is.
    for (h, s) in field.heights.iter_mut().zip(&state.sediment) {
        *h += s;
        budget.sediment_settled += s * area;
    }
    budget.water_left = state.water.iter().sum::<f64>() * area;
    budget
}

/// sin α of the terrain's tilt at (i, j) — the gradient from the pipes' neighbours,
/// (2/n)·Σ ((b_m − b)/l)·direction over the n pipes (a missing neighbour at the grid's
/// border counts as level) — and the lowest and highest neighbour (the point's own height
/// where it has none).
fn tilt_and_range(b: &[f64], cols: usize, rows: usize, i: usize, j: usize, pipes: &[Pipe]) -> (f64, f64, f64) {
    let here = b[j * cols + i];
    let mut gradient = [0.0f64; 2];
    let (mut lowest, mut highest) = (here, here);
    for p in pipes {
        let (ni, nj) = (i as i64 + p.dx, j as i64 + p.dy);
        if ni < 0 || nj < 0 || ni as usize >= cols || nj as usize >= rows {
            continue;
        }
        let there = b[nj as usize * cols + ni as usize];
        (lowest, highest) = (lowest.min(there), highest.max(there));
        let rise = (there - here) / p.length;
        gradient[0] += rise * p.direction[0];
        gradient[1] += rise * p.direction[1];
    }
    let g = gradient[0].hypot(gradient[1]) * 2.0 / pipes.len() as f64;
    (g / (1.0 + g * g).sqrt(), lowest, highest)
}
