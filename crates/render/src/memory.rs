//! The process's resident memory, for the renders' reports: the peak
//! resident set during a render, so that what an integrator holds (VCM's
//! light vertices, a Metropolis bootstrap, LQMC's nothing extra — the LQMC
//! paper's point about VCM's 70 MB photon map) can be compared.
//!
//! Read from Linux's procfs (proc(5)): `VmRSS` and `VmHWM` of
//! `/proc/self/status` are the resident set and its peak, and writing `5`
//! to `/proc/self/clear_refs` (Linux ≥ 4.0) resets the peak to the
//! current resident set, so a render measures its own peak even after
//! earlier renders in the same process (a study). Where the reset is
//! refused the peak is the process's since it started, and the report
//! says so; where procfs is missing (other systems) nothing is measured.
//! Renders running at the same time in one process (tests) share the
//! measure.

/// What a render's memory measurement found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MemoryReport {
    /// The peak resident set, in bytes.
    pub peak_resident_bytes: u64,
    /// The resident set when the measurement started, in bytes.
    pub resident_bytes_at_start: u64,
    /// Whether the peak is the render's own (the peak was reset at its
    /// start); otherwise it is the process's since it started.
    pub peak_since_start: bool,
}

impl MemoryReport {
    /// One line for the command line, in MB (10⁶ bytes).
    pub fn describe(&self) -> String {
        let megabytes = |bytes: u64| bytes as f64 / 1e6;
        if self.peak_since_start {
            format!(
                "peak resident memory {:.1} MB ({:.1} MB at the render's start)",
                megabytes(self.peak_resident_bytes),
                megabytes(self.resident_bytes_at_start)
            )
        } else {
            format!(
                "peak resident memory {:.1} MB (the process's peak: it could not be reset; {:.1} MB at the render's start)",
                megabytes(self.peak_resident_bytes),
                megabytes(self.resident_bytes_at_start)
            )
        }
    }
}

/// A measurement of the peak resident memory from its start (see the
/// module docs).
#[derive(Debug, Clone, Copy)]
pub struct PeakMemoryMeasurement {
    resident_bytes_at_start: Option<u64>,
    reset: bool,
}

impl PeakMemoryMeasurement {
    /// Starts a measurement: resets the process's peak where allowed.
    pub fn start() -> Self {
        let reset = std::fs::write("/proc/self/clear_refs", "5").is_ok();
        Self {
            resident_bytes_at_start: status_field("VmRSS"),
            reset,
        }
    }

    /// The peak since [`Self::start`] (see [`MemoryReport::peak_since_start`]),
    /// or `None` where the system does not tell.
    pub fn finish(&self) -> Option<MemoryReport> {
        let peak = status_field("VmHWM")?;
        let at_start = self.resident_bytes_at_start?;
        Some(MemoryReport {
            peak_resident_bytes: peak.max(at_start),
            resident_bytes_at_start: at_start,
            peak_since_start: self.reset,
        })
    }
}

/// The value in bytes of a `kB` field of `/proc/self/status`.
fn status_field(name: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    parse_status_field(&status, name)
}

/// The value in bytes of the field `name` (`Name:   1234 kB`) of a
/// `/proc/PID/status` text.
fn parse_status_field(status: &str, name: &str) -> Option<u64> {
    status.lines().find_map(|line| {
        let rest = line.strip_prefix(name)?.strip_prefix(':')?;
        let mut words = rest.split_whitespace();
        let value: u64 = words.next()?.parse().ok()?;
        match words.next() {
            Some("kB") => Some(value * 1024),
            _ => None,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn status_fields_are_read_in_bytes() {
        let status = "Name:\tlqmc\nVmHWM:\t  204800 kB\nVmRSS:\t   10240 kB\nThreads:\t3\n";
        assert_eq!(parse_status_field(status, "VmHWM"), Some(204_800 * 1024));
        assert_eq!(parse_status_field(status, "VmRSS"), Some(10_240 * 1024));
        assert_eq!(parse_status_field(status, "VmSwap"), None);
        assert_eq!(parse_status_field(status, "Threads"), None);
    }

    /// On Linux the peak includes a buffer of 64 MB touched after the
    /// start and still held (other tests of the process may reset the peak
    /// meanwhile, never below what is resident).
    #[test]
    #[cfg(target_os = "linux")]
    fn a_touched_buffer_is_in_the_peak() {
        let measurement = PeakMemoryMeasurement::start();
        let buffer = vec![1u8; 64 << 20];
        let report = measurement.finish().expect("procfs on Linux");
        std::hint::black_box(&buffer);
        assert!(report.peak_resident_bytes >= 64 << 20, "{report:?}");
        assert!(report.describe().contains("MB"));
    }
}
