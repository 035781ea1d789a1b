//! The common interface of every point set and sequence in this crate.

/// A finite point set or an infinite sequence in the unit cube `[0, 1)^s`,
/// evaluated one coordinate at a time.
///
/// Coordinates are asked for by point index and dimension so that a renderer can
/// draw exactly the dimensions a path needs, in any order, from any thread.
/// Implementations are immutable after construction (randomizations are fixed
/// when the randomized set is built from a seed), hence `Send + Sync`.
pub trait PointSet: Send + Sync {
    /// Number of dimensions this set provides; dimensions `0..dimensions()` are valid.
    fn dimensions(&self) -> usize;

    /// Number of points of a finite point set, `None` for an extensible sequence.
    fn len(&self) -> Option<u64>;

    /// True for a finite set of no points (never the case for the sets here).
    fn is_empty(&self) -> bool {
        self.len() == Some(0)
    }

    /// Coordinate `dimension` of point `index`, in `[0, 1)`.
    ///
    /// Callers keep `dimension < self.dimensions()` and, for finite sets,
    /// `index < len`; implementations may panic otherwise (the CLI and the
    /// renderer validate first, see [`check_request`]).
    fn sample(&self, index: u64, dimension: usize) -> f64;

    /// Writes the first `out.len()` coordinates of point `index` into `out`.
    fn point(&self, index: u64, out: &mut [f64]) {
        for (dimension, value) in out.iter_mut().enumerate() {
            *value = self.sample(index, dimension);
        }
    }
}

impl<T: PointSet + ?Sized> PointSet for Box<T> {
    fn dimensions(&self) -> usize {
        (**self).dimensions()
    }
    fn len(&self) -> Option<u64> {
        (**self).len()
    }
    fn sample(&self, index: u64, dimension: usize) -> f64 {
        (**self).sample(index, dimension)
    }
    fn point(&self, index: u64, out: &mut [f64]) {
        (**self).point(index, out)
    }
}

/// Why a point set cannot be built or a request cannot be served.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PointSetError {
    /// More dimensions were asked for than the construction supports.
    TooManyDimensions { requested: usize, supported: usize },
    /// More points were asked for than the construction supports.
    TooManyPoints { requested: u64, supported: u64 },
    /// A parameter is outside its valid range; the message says which.
    InvalidParameter(String),
}

impl std::fmt::Display for PointSetError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::TooManyDimensions {
                requested,
                supported,
            } => write!(
                f,
                "{requested} dimensions requested but at most {supported} are supported"
            ),
            Self::TooManyPoints {
                requested,
                supported,
            } => write!(
                f,
                "{requested} points requested but at most {supported} are supported"
            ),
            Self::InvalidParameter(message) => f.write_str(message),
        }
    }
}

impl std::error::Error for PointSetError {}

/// Checks that points `start .. start + count` with `dimensions` coordinates can
/// be drawn from `set`.
pub fn check_request(
    set: &dyn PointSet,
    start: u64,
    count: u64,
    dimensions: usize,
) -> Result<(), PointSetError> {
    if dimensions > set.dimensions() {
        return Err(PointSetError::TooManyDimensions {
            requested: dimensions,
            supported: set.dimensions(),
        });
    }
    if let Some(len) = set.len() {
        let end = start.saturating_add(count);
        if end > len {
            return Err(PointSetError::TooManyPoints {
                requested: end,
                supported: len,
            });
        }
    }
    Ok(())
}
