//! What LQMC counts while rendering (`lqmc render --stats`): explorations
//! per class, the members tried and kept, failures per reason, and the time
//! spent in the closest-lattice-point search.

use super::classification::PathClass;
use std::hint::black_box;
use std::time::Instant;

/// Why a lattice member contributes nothing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FailureReason {
    /// The reconnection segment (or a rebuilt vertex's light connection) is
    /// blocked.
    Occluded,
    /// The reconnection ray hit the seed's next vertex's surface more than
    /// the tolerance away from it, or another surface behind it.
    Misplaced,
    /// A rebuilt prefix ray left the scene or hit a surface without material.
    Escaped,
    /// A vertex's sampled mode (reflect/refract, specular/diffuse) differs
    /// from the seed's.
    ModeChange,
    /// A member seen from the camera lies outside the image.
    OutsideImage,
    /// Russian roulette with the seed's number ends the member.
    RussianRoulette,
    /// The member's class or breakup probability excludes it from this
    /// exploration.
    ClassChange,
    /// A zero BSDF value or density, or no emission.
    Evaluation,
}

impl FailureReason {
    /// Every reason, in the order statistics list them.
    pub const ALL: [FailureReason; 8] = [
        FailureReason::Occluded,
        FailureReason::Misplaced,
        FailureReason::Escaped,
        FailureReason::ModeChange,
        FailureReason::OutsideImage,
        FailureReason::RussianRoulette,
        FailureReason::ClassChange,
        FailureReason::Evaluation,
    ];

    /// Index in [`FailureReason::ALL`].
    pub fn index(self) -> usize {
        Self::ALL
            .iter()
            .position(|reason| *reason == self)
            .unwrap_or(0)
    }

    /// A short name.
    pub fn name(self) -> &'static str {
        match self {
            FailureReason::Occluded => "occluded",
            FailureReason::Misplaced => "misplaced reconnection",
            FailureReason::Escaped => "prefix escaped",
            FailureReason::ModeChange => "mode change",
            FailureReason::OutsideImage => "outside image",
            FailureReason::RussianRoulette => "russian roulette",
            FailureReason::ClassChange => "class or breakup change",
            FailureReason::Evaluation => "zero value",
        }
    }
}

/// Counters of an LQMC render (summed over tiles).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct LqmcStatistics {
    /// Seeds traced by the path tracer alone: none of their events could
    /// be explored (`seed_screen`).
    pub screened_seeds: u64,
    /// Seeds traced again to be recorded: the screen found an event that
    /// could be explored.
    pub retraced_seeds: u64,
    /// Splat events of recorded seed paths with a non-zero contribution.
    pub events: u64,
    /// Events splatted without exploration.
    pub direct_splats: u64,
    /// Explorations per class ([`PathClass::ALL`] order).
    pub explorations: [u64; 4],
    /// Members evaluated per class.
    pub members: [u64; 4],
    /// Members that contributed per class.
    pub valid_members: [u64; 4],
    /// Failed members per reason ([`FailureReason::ALL`] order).
    pub failures: [u64; 8],
    /// Explorations abandoned because the seed's own member failed (the
    /// seed is then splatted directly; see `exploration::explore`).
    pub empty_explorations: u64,
    /// Of those, the seed's own member's failure reason
    /// ([`FailureReason::ALL`] order).
    pub seed_failures: [u64; 8],
    /// Seeds whose value walk failed on their own recorded path, so that
    /// they could not be explored: the walk recomputes directions from the
    /// vertex positions, and where a decision is on a knife's edge (a
    /// reflect-or-refract choice or Russian roulette at a grazing angle,
    /// deep in a specular chain) it can come out otherwise than in the path
    /// tracer. They are splatted directly with the path tracer's value.
    pub unevaluable_seeds: u64,
    /// Explorations per breakup vertex b = 0, 1, 2, ≥ 3.
    pub breakups: [u64; 4],
    /// Explorations that explore a free-flight distance (a medium vertex
    /// in the prefix).
    pub medium_explorations: u64,
    /// Valid members whose steps after the breakup's next vertex and whose
    /// end were the seed's (no evaluation of those vertices again).
    pub reusing_members: u64,
    /// Rays traced for members (prefix rebuilds, reconnections, next-event
    /// shadow rays of rebuilt vertices).
    pub member_rays: u64,
    /// Members of the explorations whose member loop was timed, and that
    /// time (every 16th exploration).
    pub timed_members: u64,
    /// See [`LqmcStatistics::timed_members`].
    pub timed_member_nanoseconds: u64,
    /// The closest-lattice-point search's calls and sampled time.
    pub closest_point: ClosestPointTiming,
}

/// The time of the closest-point search, measured on a sample of its calls.
///
/// One call takes tens of nanoseconds, about what reading the clock twice
/// costs, so timing every call would mostly measure the timer (and slow the
/// render). Instead every [`Self::SAMPLING_PERIOD`]-th call (by count, so the
/// sample is deterministic) is timed as a batch of [`Self::BATCH`] identical
/// searches between two clock reads, which spreads the timer's cost over the
/// batch; the total is the mean time per timed search times the number of
/// calls. The repeated searches add about `BATCH / SAMPLING_PERIOD` of the
/// search's own cost to the render (under 1 % of it while the share is).
/// They run on warm caches, so the estimate leans low where the first
/// search of a batch misses the cache; `lqmc-fig7.md` cross-checks it with
/// instruction counts.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ClosestPointTiming {
    /// Closest-point searches of the render.
    pub searches: u64,
    /// Searches inside timed batches (the repeats included).
    pub timed_searches: u64,
    /// Nanoseconds of the timed batches.
    pub timed_nanoseconds: u64,
}

impl ClosestPointTiming {
    /// One call in this many is timed.
    pub const SAMPLING_PERIOD: u64 = 64;
    /// Searches per timed batch (the call itself and its repeats).
    pub const BATCH: u64 = 16;

    /// Runs `search` once (its result is returned) and, on sampled calls,
    /// `BATCH − 1` more times inside the timer. `search` must be a pure
    /// function of its captures (the closest-point search is).
    pub fn measure<T>(&mut self, mut search: impl FnMut() -> T) -> T {
        self.searches += 1;
        if self.searches % Self::SAMPLING_PERIOD != 1 {
            return search();
        }
        let start = Instant::now();
        let result = search();
        for _ in 1..Self::BATCH {
            black_box(search());
        }
        self.timed_nanoseconds += start.elapsed().as_nanos() as u64;
        self.timed_searches += Self::BATCH;
        result
    }

    /// Mean nanoseconds per search in the timed batches.
    pub fn nanoseconds_per_search(&self) -> f64 {
        self.timed_nanoseconds as f64 / self.timed_searches.max(1) as f64
    }

    /// Estimated CPU seconds of all searches of the render (the repeats of the
    /// timed batches not counted).
    pub fn estimated_seconds(&self) -> f64 {
        self.nanoseconds_per_search() * self.searches as f64 * 1e-9
    }

    /// Adds another tile's counts.
    pub fn add(&mut self, other: &ClosestPointTiming) {
        self.searches += other.searches;
        self.timed_searches += other.timed_searches;
        self.timed_nanoseconds += other.timed_nanoseconds;
    }
}

impl LqmcStatistics {
    /// Adds another tile's counters.
    pub fn add(&mut self, other: &LqmcStatistics) {
        self.screened_seeds += other.screened_seeds;
        self.retraced_seeds += other.retraced_seeds;
        self.events += other.events;
        self.direct_splats += other.direct_splats;
        for i in 0..4 {
            self.explorations[i] += other.explorations[i];
            self.members[i] += other.members[i];
            self.valid_members[i] += other.valid_members[i];
            self.breakups[i] += other.breakups[i];
        }
        for i in 0..8 {
            self.failures[i] += other.failures[i];
            self.seed_failures[i] += other.seed_failures[i];
        }
        self.empty_explorations += other.empty_explorations;
        self.unevaluable_seeds += other.unevaluable_seeds;
        self.medium_explorations += other.medium_explorations;
        self.reusing_members += other.reusing_members;
        self.member_rays += other.member_rays;
        self.timed_members += other.timed_members;
        self.timed_member_nanoseconds += other.timed_member_nanoseconds;
        self.closest_point.add(&other.closest_point);
    }

    /// Counts a failed member.
    pub fn fail(&mut self, reason: FailureReason) {
        self.failures[reason.index()] += 1;
    }

    /// A human-readable report; `render_seconds` is the render's wall time
    /// and `threads` the number of threads (the search time is CPU time).
    pub fn report(&self, render_seconds: f64, threads: usize) -> String {
        let mut lines = Vec::new();
        let explorations: u64 = self.explorations.iter().sum();
        let members: u64 = self.members.iter().sum();
        let failures: u64 = self.failures.iter().sum();
        if self.screened_seeds + self.retraced_seeds > 0 {
            lines.push(format!(
                "LQMC: {} seeds path-traced alone (no event could be explored), {} traced again to be recorded",
                self.screened_seeds, self.retraced_seeds
            ));
        }
        lines.push(format!(
            "LQMC: {} splat events, {} explored, {} splatted directly",
            self.events, explorations, self.direct_splats
        ));
        for class in PathClass::ALL {
            let i = class.index();
            if self.explorations[i] == 0 {
                continue;
            }
            lines.push(format!(
                "  {:8} {:>10} explorations, mean set size {:.2} of {:.1} members",
                class.name(),
                self.explorations[i],
                self.valid_members[i] as f64 / self.explorations[i] as f64,
                self.members[i] as f64 / self.explorations[i] as f64,
            ));
        }
        if self.medium_explorations > 0 {
            lines.push(format!(
                "  {} explorations with free-flight distances (media)",
                self.medium_explorations
            ));
        }
        lines.push(format!(
            "  breakup b = 0 / 1 / 2 / >=3: {} / {} / {} / {}",
            self.breakups[0], self.breakups[1], self.breakups[2], self.breakups[3]
        ));
        lines.push(format!(
            "  failed members: {} of {} ({:.2} %); {} explorations abandoned (the seed failed in its own set: splatted directly)",
            failures,
            members,
            100.0 * failures as f64 / members.max(1) as f64,
            self.empty_explorations
        ));
        if self.unevaluable_seeds > 0 {
            lines.push(format!(
                "  {} seeds not explored because their value walk disagreed with the path tracer (splatted directly)",
                self.unevaluable_seeds
            ));
        }
        let all_members: u64 = self.members.iter().sum();
        lines.push(format!(
            "  cost per member: {:.0} ns CPU (timed on {} members, every 16th exploration), {:.2} rays",
            self.timed_member_nanoseconds as f64 / self.timed_members.max(1) as f64,
            self.timed_members,
            self.member_rays as f64 / all_members.max(1) as f64
        ));
        let valid: u64 = self.valid_members.iter().sum();
        lines.push(format!(
            "  members evaluated from the seed's steps after x_(b+1): {} of {} valid ({:.1} %)",
            self.reusing_members,
            valid,
            100.0 * self.reusing_members as f64 / valid.max(1) as f64
        ));
        for reason in FailureReason::ALL {
            let count = self.failures[reason.index()];
            if count > 0 {
                lines.push(format!(
                    "    {:24} {:>10} ({:.2} % of members; {} seeds in their own set)",
                    reason.name(),
                    count,
                    100.0 * count as f64 / members.max(1) as f64,
                    self.seed_failures[reason.index()]
                ));
            }
        }
        let search_seconds = self.closest_point.estimated_seconds();
        let cpu_seconds = render_seconds * threads.max(1) as f64;
        lines.push(format!(
            "  closest-point search: {} calls x {:.1} ns = {:.4} s CPU, {:.3} % of {:.2} s render time x {} threads",
            self.closest_point.searches,
            self.closest_point.nanoseconds_per_search(),
            search_seconds,
            100.0 * search_seconds / cpu_seconds.max(1e-12),
            render_seconds,
            threads.max(1)
        ));
        lines.join("\n")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sampled_timing_counts_every_call_and_times_a_batch_per_period() {
        let mut timing = ClosestPointTiming::default();
        let mut runs = 0u64;
        let calls = 3 * ClosestPointTiming::SAMPLING_PERIOD;
        for call in 0..calls {
            let result = timing.measure(|| {
                runs += 1;
                call
            });
            assert_eq!(result, call);
        }
        assert_eq!(timing.searches, calls);
        assert_eq!(timing.timed_searches, 3 * ClosestPointTiming::BATCH);
        assert_eq!(runs, calls + 3 * (ClosestPointTiming::BATCH - 1));
        let mut total = ClosestPointTiming::default();
        total.add(&timing);
        total.add(&timing);
        assert_eq!(total.searches, 2 * calls);
        assert!(
            (total.estimated_seconds() - 2.0 * timing.estimated_seconds()).abs()
                <= 1e-12 + 1e-9 * timing.estimated_seconds()
        );
    }
}
