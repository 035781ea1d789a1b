//! What LQMC counts while rendering (`lqmc render --stats`): explorations
//! per class, the members tried and kept, failures per reason, and the time
//! spent in the closest-lattice-point search.

use super::classification::PathClass;

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
    /// Splat events of seed paths with a non-zero contribution.
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
    /// Explorations in which every member failed (nothing splatted).
    pub empty_explorations: u64,
    /// Explorations per breakup vertex b = 0, 1, 2, ≥ 3.
    pub breakups: [u64; 4],
    /// Nanoseconds spent in the closest-lattice-point search.
    pub closest_point_nanoseconds: u64,
    /// Explorations that explore a free-flight distance (a medium vertex
    /// in the prefix).
    pub medium_explorations: u64,
}

impl LqmcStatistics {
    /// Adds another tile's counters.
    pub fn add(&mut self, other: &LqmcStatistics) {
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
        }
        self.empty_explorations += other.empty_explorations;
        self.closest_point_nanoseconds += other.closest_point_nanoseconds;
        self.medium_explorations += other.medium_explorations;
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
            "  failed members: {} of {} ({:.2} %), {} explorations without any",
            failures,
            members,
            100.0 * failures as f64 / members.max(1) as f64,
            self.empty_explorations
        ));
        for reason in FailureReason::ALL {
            let count = self.failures[reason.index()];
            if count > 0 {
                lines.push(format!(
                    "    {:24} {:>10} ({:.2} % of members)",
                    reason.name(),
                    count,
                    100.0 * count as f64 / members.max(1) as f64
                ));
            }
        }
        let search_seconds = self.closest_point_nanoseconds as f64 * 1e-9;
        let cpu_seconds = render_seconds * threads.max(1) as f64;
        lines.push(format!(
            "  closest-point search: {:.4} s CPU, {:.3} % of {:.2} s render time x {} threads",
            search_seconds,
            100.0 * search_seconds / cpu_seconds.max(1e-12),
            render_seconds,
            threads.max(1)
        ));
        lines.join("\n")
    }
}
