//! The SW/HW split chosen by measured cost ([`FrameSettings::AUTO_HW_THRESHOLD`], the default):
//! which threshold serves a scene best depends on the GPU (how fast its graphics pipeline draws
//! against the software rasterizer) and on what is drawn (close walls want hardware, fields of
//! tiny triangles want none), so no fixed value is right everywhere. [`SplitTuner`] climbs a
//! ladder of thresholds ([`SPLIT_LADDER`]) by the GPU time of whole frames: it measures its
//! choice, the neighbouring thresholds and software only over a few frames each, moves to the
//! fastest when it beats the choice by more than [`SPLIT_MARGIN`], and otherwise keeps its choice
//! for ever longer spells before it looks again. Software only is always a candidate, so the
//! split is never measurably slower than it, even where the steps between are too small to
//! climb. The split changes no pixel of the image (both rasterizers write the same values,
//! `tests/frame.rs`), only the time (and what the `hwsw` view and the SW/HW counters show: the
//! `hwsw` view is drawn with the choice, never a threshold being tried).
//!
//! [`FrameSettings::AUTO_HW_THRESHOLD`]: crate::passes::view::FrameSettings::AUTO_HW_THRESHOLD

/// `hw_threshold_px` that sends every cluster to the software rasterizer (but those reaching the
/// near plane, which it cannot clip).
pub const SOFTWARE_ONLY_PX: f32 = 1.0e6;

/// The thresholds the tuner chooses from (pixels, ascending; the last is software only).
pub const SPLIT_LADDER: [f32; 7] = [8.0, 16.0, 32.0, 64.0, 128.0, 256.0, SOFTWARE_ONLY_PX];

/// Where the tuner starts: the fixed default of before ([`crate::shared::DEFAULT_HW_THRESHOLD_PX`]).
const START: usize = 3;
const _: () = assert!(SPLIT_LADDER[START] == crate::shared::DEFAULT_HW_THRESHOLD_PX);

/// Frames measured per threshold in a round (their median is its cost).
pub const SPLIT_WINDOW: usize = 8;

/// A candidate must be faster than the choice by this fraction to take its place (the median of
/// a window varies by a few tenths of a percent on a steady GPU).
pub const SPLIT_MARGIN: f64 = 0.005;

/// Frames between rounds after the first that keeps its choice; doubled by each further such
/// round, up to [`SPLIT_MAX_HOLD`].
const FIRST_HOLD: u32 = 64;
const SPLIT_MAX_HOLD: u32 = 4096;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stage {
    /// Measuring candidate `k` of the round (0: the choice, 1: the next threshold up, 2: down,
    /// 3: software only).
    Measure(usize),
    /// Keeping the choice for `n` more frames.
    Hold(u32),
}

/// Chooses the SW/HW split by measured frame time (see the module's documentation).
#[derive(Clone, Debug)]
pub struct SplitTuner {
    /// Index of the chosen threshold in [`SPLIT_LADDER`].
    at: usize,
    stage: Stage,
    samples: Vec<f64>,
    /// Median frame time of the round's candidates (choice, up, down, software only).
    medians: [Option<f64>; 4],
    /// Frames of the next hold that keeps the choice.
    hold: u32,
    /// Rounds run, and whether the last one kept its choice.
    rounds: u32,
    kept: bool,
}

impl Default for SplitTuner {
    fn default() -> Self {
        Self::new()
    }
}

impl SplitTuner {
    /// Starts at the fixed default, measuring it.
    pub fn new() -> Self {
        Self {
            at: START,
            stage: Stage::Measure(0),
            samples: Vec::with_capacity(SPLIT_WINDOW),
            medians: [None; 4],
            hold: FIRST_HOLD,
            rounds: 0,
            kept: false,
        }
    }

    /// The ladder index candidate `k` of a round stands for, if it exists.
    fn candidate(&self, k: usize) -> Option<usize> {
        let last = SPLIT_LADDER.len() - 1;
        match k {
            0 => Some(self.at),
            1 => (self.at < last).then_some(self.at + 1),
            2 => self.at.checked_sub(1),
            // Software only, unless it is the choice or the step up.
            _ => (self.at + 1 < last).then_some(last),
        }
    }

    /// The threshold the next frame should use.
    pub fn threshold(&self) -> f32 {
        match self.stage {
            Stage::Measure(k) => SPLIT_LADDER[self.candidate(k).unwrap_or(self.at)],
            Stage::Hold(_) => SPLIT_LADDER[self.at],
        }
    }

    /// The threshold chosen so far (what the tuner holds between its rounds).
    pub fn chosen(&self) -> f32 {
        SPLIT_LADDER[self.at]
    }

    /// Whether the last round kept its choice and the tuner now holds it: the choice is the
    /// fastest of its neighbours as measured.
    pub fn settled(&self) -> bool {
        self.kept && matches!(self.stage, Stage::Hold(_))
    }

    /// Rounds run so far.
    pub fn rounds(&self) -> u32 {
        self.rounds
    }

    /// A completed frame drawn with `threshold` took `gpu_ms` (all passes). Frames drawn with
    /// another threshold than the one asked for now (frames in flight from before a change) and
    /// frames without a time are ignored.
    pub fn observe(&mut self, threshold: f32, gpu_ms: f64) {
        if threshold != self.threshold() || !(gpu_ms.is_finite() && gpu_ms > 0.0) {
            return;
        }
        match self.stage {
            Stage::Hold(0) => self.start_round(),
            Stage::Hold(n) => self.stage = Stage::Hold(n - 1),
            Stage::Measure(k) => {
                self.samples.push(gpu_ms);
                if self.samples.len() < SPLIT_WINDOW {
                    return;
                }
                self.medians[k] = Some(median(&mut self.samples));
                self.samples.clear();
                match (k + 1..4).find(|&j| self.candidate(j).is_some()) {
                    Some(j) => self.stage = Stage::Measure(j),
                    None => self.decide(),
                }
            }
        }
    }

    /// Starts a fresh round from the current choice (what was measured before, on other frames,
    /// does not count).
    pub fn restart(&mut self) {
        self.kept = false;
        self.start_round();
    }

    fn start_round(&mut self) {
        self.stage = Stage::Measure(0);
        self.samples.clear();
        self.medians = [None; 4];
    }

    /// Ends a round: moves to the fastest candidate when it beats the choice by the margin.
    fn decide(&mut self) {
        self.rounds += 1;
        let mine = self.medians[0].unwrap_or(f64::INFINITY);
        let best = (1..4)
            .filter_map(|k| Some((k, self.medians[k]?)))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        match best {
            Some((k, ms)) if ms < mine * (1.0 - SPLIT_MARGIN) => {
                self.at = self.candidate(k).unwrap_or(self.at);
                self.kept = false;
                self.hold = FIRST_HOLD;
                // Look again at once: the next step may be faster still.
                self.start_round();
            }
            _ => {
                self.kept = true;
                self.stage = Stage::Hold(self.hold);
                self.hold = (self.hold * 2).min(SPLIT_MAX_HOLD);
            }
        }
    }
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_unstable_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Drives a tuner with a cost per threshold until it settles (or `frames` run out).
    fn run(cost: impl Fn(f32) -> f64, frames: usize) -> SplitTuner {
        let mut t = SplitTuner::new();
        for _ in 0..frames {
            let th = t.threshold();
            t.observe(th, cost(th));
            if t.settled() {
                break;
            }
        }
        t
    }

    #[test]
    fn climbs_to_the_fastest_threshold_and_settles() {
        // Software only is cheapest by 1.4 % (foliage on the H100), in steps too small to climb:
        // the tuner goes there in its first round.
        let t = run(
            |th| {
                if th >= SOFTWARE_ONLY_PX {
                    4.24
                } else {
                    4.30 - th as f64 * 1e-5
                }
            },
            1000,
        );
        assert!(t.settled());
        assert_eq!(t.chosen(), SOFTWARE_ONLY_PX);
        assert_eq!(t.rounds(), 2);
        // A valley at 16 px (close walls): it walks down and stops there.
        let t = run(|th| ((th as f64).log2() - 4.0).abs() * 0.1 + 1.0, 1000);
        assert!(t.settled());
        assert_eq!(t.chosen(), 16.0);
        // Flat within the margin: it keeps the start.
        let t = run(|th| 1.0 + (th as f64).log2() * 1e-5, 1000);
        assert!(t.settled());
        assert_eq!(t.chosen(), 64.0);
        assert_eq!(t.rounds(), 1);
    }

    #[test]
    fn ignores_frames_of_other_thresholds_and_frames_without_time() {
        let mut t = SplitTuner::new();
        for _ in 0..100 {
            t.observe(8.0, 1.0);
            t.observe(t.threshold(), 0.0);
            t.observe(t.threshold(), f64::NAN);
        }
        assert_eq!(t.rounds(), 0);
        assert_eq!(t.threshold(), 64.0);
    }

    #[test]
    fn holds_its_choice_for_longer_spells_then_looks_again() {
        let mut t = SplitTuner::new();
        let cost = |th: f32| 1.0 + (th as f64 - 64.0).abs() * 1e-3;
        let mut probes = Vec::new();
        for f in 0..20_000 {
            let th = t.threshold();
            if th != t.chosen() {
                probes.push(f);
            }
            t.observe(th, cost(th));
        }
        assert_eq!(t.chosen(), 64.0);
        // Each round probes three other thresholds for a window each; rounds grow further
        // apart (holds of 64, 128, ... frames), so probing stays rare.
        assert!(t.rounds() >= 4, "{} rounds", t.rounds());
        assert!(probes.len() <= 3 * SPLIT_WINDOW * t.rounds() as usize);
        // At the longest hold a round comes every 4,096 frames: under 1 % of frames probe.
        let late = probes.iter().filter(|&&f| f >= 10_000).count();
        assert!(
            late <= 3 * 3 * SPLIT_WINDOW,
            "{late} probing frames in the last 10,000"
        );
    }
}
