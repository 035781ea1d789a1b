//! A four-lane single-precision vector for the BVH node and triangle tests:
//! SSE2 on x86_64 (always available there), plain arrays elsewhere.
//!
//! An eight-lane vector ([`F32x8`], AVX) serves the BVH node test on CPUs
//! that have AVX2 (chosen at run time, see [`Avx2`]).
//!
//! Only what the traversal needs is provided. Every operation is a lane-wise
//! IEEE single-precision operation (no fused multiply–add), so a lane computes
//! exactly what the scalar code computes for the same inputs; the watertight
//! triangle test relies on that.

#[cfg(target_arch = "x86_64")]
use std::arch::x86_64::*;

/// Four `f32` lanes.
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub(crate) struct F32x4(
    #[cfg(target_arch = "x86_64")] __m128,
    #[cfg(not(target_arch = "x86_64"))] [f32; 4],
);

/// A lane mask from a comparison (all bits of a lane set where true).
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub(crate) struct Mask4(
    #[cfg(target_arch = "x86_64")] __m128,
    #[cfg(not(target_arch = "x86_64"))] [bool; 4],
);

// SAFETY (for every `unsafe` block in this file): SSE2 is part of the x86_64
// baseline, so its intrinsics are always available; loads and stores go
// through references to `[f32; 4]`, which are valid for 16 bytes.
#[cfg(target_arch = "x86_64")]
impl F32x4 {
    #[inline(always)]
    pub(crate) fn splat(value: f32) -> Self {
        unsafe { Self(_mm_set1_ps(value)) }
    }
    #[inline(always)]
    pub(crate) fn load(values: &[f32; 4]) -> Self {
        unsafe { Self(_mm_loadu_ps(values.as_ptr())) }
    }
    #[inline(always)]
    pub(crate) fn to_array(self) -> [f32; 4] {
        let mut out = [0.0; 4];
        unsafe { _mm_storeu_ps(out.as_mut_ptr(), self.0) };
        out
    }
    /// The 4 × 4 transpose: lane `j` of row `i` of the result is lane `i`
    /// of `rows[j]` (turns four loaded `[x, y, z, w]` points into x, y, z and w
    /// rows).
    #[inline(always)]
    pub(crate) fn transpose(rows: [Self; 4]) -> [Self; 4] {
        unsafe {
            let low01 = _mm_unpacklo_ps(rows[0].0, rows[1].0);
            let low23 = _mm_unpacklo_ps(rows[2].0, rows[3].0);
            let high01 = _mm_unpackhi_ps(rows[0].0, rows[1].0);
            let high23 = _mm_unpackhi_ps(rows[2].0, rows[3].0);
            [
                Self(_mm_movelh_ps(low01, low23)),
                Self(_mm_movehl_ps(low23, low01)),
                Self(_mm_movelh_ps(high01, high23)),
                Self(_mm_movehl_ps(high23, high01)),
            ]
        }
    }
    #[inline(always)]
    pub(crate) fn add(self, other: Self) -> Self {
        unsafe { Self(_mm_add_ps(self.0, other.0)) }
    }
    #[inline(always)]
    pub(crate) fn sub(self, other: Self) -> Self {
        unsafe { Self(_mm_sub_ps(self.0, other.0)) }
    }
    #[inline(always)]
    pub(crate) fn mul(self, other: Self) -> Self {
        unsafe { Self(_mm_mul_ps(self.0, other.0)) }
    }
    #[inline(always)]
    pub(crate) fn div(self, other: Self) -> Self {
        unsafe { Self(_mm_div_ps(self.0, other.0)) }
    }
    /// Lane-wise minimum (inputs must not be NaN).
    #[inline(always)]
    pub(crate) fn min(self, other: Self) -> Self {
        unsafe { Self(_mm_min_ps(self.0, other.0)) }
    }
    /// Lane-wise maximum (inputs must not be NaN).
    #[inline(always)]
    pub(crate) fn max(self, other: Self) -> Self {
        unsafe { Self(_mm_max_ps(self.0, other.0)) }
    }
    /// Flips the sign of the lanes where `sign_source` has its sign bit set
    /// (`self · sign(sign_source)` for non-zero sources).
    #[inline(always)]
    pub(crate) fn xor_sign_of(self, sign_source: Self) -> Self {
        unsafe {
            let sign = _mm_and_ps(sign_source.0, _mm_set1_ps(-0.0));
            Self(_mm_xor_ps(self.0, sign))
        }
    }
    /// `|self|`.
    #[inline(always)]
    pub(crate) fn abs(self) -> Self {
        unsafe { Self(_mm_andnot_ps(_mm_set1_ps(-0.0), self.0)) }
    }
    #[inline(always)]
    pub(crate) fn lt(self, other: Self) -> Mask4 {
        unsafe { Mask4(_mm_cmplt_ps(self.0, other.0)) }
    }
    #[inline(always)]
    pub(crate) fn le(self, other: Self) -> Mask4 {
        unsafe { Mask4(_mm_cmple_ps(self.0, other.0)) }
    }
    #[inline(always)]
    pub(crate) fn gt(self, other: Self) -> Mask4 {
        unsafe { Mask4(_mm_cmpgt_ps(self.0, other.0)) }
    }
    #[inline(always)]
    pub(crate) fn eq(self, other: Self) -> Mask4 {
        unsafe { Mask4(_mm_cmpeq_ps(self.0, other.0)) }
    }
}

#[cfg(target_arch = "x86_64")]
impl Mask4 {
    #[inline(always)]
    pub(crate) fn and(self, other: Self) -> Self {
        unsafe { Self(_mm_and_ps(self.0, other.0)) }
    }
    #[inline(always)]
    pub(crate) fn or(self, other: Self) -> Self {
        unsafe { Self(_mm_or_ps(self.0, other.0)) }
    }
    /// `self & !other`.
    #[inline(always)]
    pub(crate) fn and_not(self, other: Self) -> Self {
        unsafe { Self(_mm_andnot_ps(other.0, self.0)) }
    }
    /// Bit `i` set where lane `i` is true.
    #[inline(always)]
    pub(crate) fn bits(self) -> u32 {
        unsafe { _mm_movemask_ps(self.0) as u32 }
    }
}

/// Proof that the CPU supports AVX2: the only way to make an [`F32x8`], so
/// that its AVX instructions never run on a processor without them.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Avx2(());

#[cfg(target_arch = "x86_64")]
impl Avx2 {
    /// `Some` if this CPU supports AVX2 (the answer is cached by the
    /// standard library), unless the environment variable `LQMC_NO_AVX2` is
    /// set: then the SSE code runs, as on older CPUs (for A/B measurements
    /// and for testing that code end to end).
    pub(crate) fn detect() -> Option<Self> {
        let disabled = std::env::var_os("LQMC_NO_AVX2").is_some();
        (!disabled && is_x86_feature_detected!("avx2")).then_some(Self(()))
    }
}

/// Eight `f32` lanes (AVX), lane-wise IEEE operations as [`F32x4`]. Made
/// only with an [`Avx2`] proof; meant for code inlined into functions
/// compiled with `#[target_feature(enable = "avx2")]`.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub(crate) struct F32x8(__m256);

// SAFETY (for every `unsafe` block of `F32x8`): an `F32x8` exists only if an
// `Avx2` proof did, so the CPU supports AVX; loads and stores go through
// references to eight contiguous `f32`s (`[[f32; 4]; 2]` has no padding),
// valid for 32 bytes.
#[cfg(target_arch = "x86_64")]
impl F32x8 {
    #[inline(always)]
    pub(crate) fn splat(_: Avx2, value: f32) -> Self {
        unsafe { Self(_mm256_set1_ps(value)) }
    }
    /// The eight values of two 4-lane rows.
    #[inline(always)]
    pub(crate) fn load(_: Avx2, values: &[[f32; 4]; 2]) -> Self {
        unsafe { Self(_mm256_loadu_ps(values.as_ptr().cast::<f32>())) }
    }
    #[inline(always)]
    pub(crate) fn to_array(self) -> [f32; 8] {
        let mut out = [0.0; 8];
        unsafe { _mm256_storeu_ps(out.as_mut_ptr(), self.0) };
        out
    }
    #[inline(always)]
    pub(crate) fn sub(self, other: Self) -> Self {
        unsafe { Self(_mm256_sub_ps(self.0, other.0)) }
    }
    #[inline(always)]
    pub(crate) fn mul(self, other: Self) -> Self {
        unsafe { Self(_mm256_mul_ps(self.0, other.0)) }
    }
    /// Lane-wise minimum (inputs must not be NaN; the second operand is
    /// returned on ties, as `minps` does).
    #[inline(always)]
    pub(crate) fn min(self, other: Self) -> Self {
        unsafe { Self(_mm256_min_ps(self.0, other.0)) }
    }
    /// Lane-wise maximum (inputs must not be NaN).
    #[inline(always)]
    pub(crate) fn max(self, other: Self) -> Self {
        unsafe { Self(_mm256_max_ps(self.0, other.0)) }
    }
    /// Bit `i` set where lane `i` of `self` is `<=` that of `other`.
    #[inline(always)]
    pub(crate) fn le_bits(self, other: Self) -> u32 {
        unsafe { _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(self.0, other.0)) as u32 }
    }
}

/// Asks the processor to bring the cache line holding `address` into all
/// cache levels (a hint: no effect on results; nothing happens off x86_64).
#[inline(always)]
pub(crate) fn prefetch<T>(address: *const T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch never faults and reads nothing observable, whatever
    // the address.
    #[allow(unused_unsafe)]
    unsafe {
        _mm_prefetch::<_MM_HINT_T0>(address.cast::<i8>())
    };
    #[cfg(not(target_arch = "x86_64"))]
    let _ = address;
}

#[cfg(not(target_arch = "x86_64"))]
impl F32x4 {
    #[inline(always)]
    fn map2(self, other: Self, f: impl Fn(f32, f32) -> f32) -> Self {
        Self(std::array::from_fn(|i| f(self.0[i], other.0[i])))
    }
    #[inline(always)]
    fn compare(self, other: Self, f: impl Fn(f32, f32) -> bool) -> Mask4 {
        Mask4(std::array::from_fn(|i| f(self.0[i], other.0[i])))
    }
    #[inline(always)]
    pub(crate) fn splat(value: f32) -> Self {
        Self([value; 4])
    }
    #[inline(always)]
    pub(crate) fn load(values: &[f32; 4]) -> Self {
        Self(*values)
    }
    #[inline(always)]
    pub(crate) fn to_array(self) -> [f32; 4] {
        self.0
    }
    pub(crate) fn transpose(rows: [Self; 4]) -> [Self; 4] {
        std::array::from_fn(|i| Self(std::array::from_fn(|j| rows[j].0[i])))
    }
    #[inline(always)]
    pub(crate) fn add(self, other: Self) -> Self {
        self.map2(other, |a, b| a + b)
    }
    #[inline(always)]
    pub(crate) fn sub(self, other: Self) -> Self {
        self.map2(other, |a, b| a - b)
    }
    #[inline(always)]
    pub(crate) fn mul(self, other: Self) -> Self {
        self.map2(other, |a, b| a * b)
    }
    #[inline(always)]
    pub(crate) fn div(self, other: Self) -> Self {
        self.map2(other, |a, b| a / b)
    }
    #[inline(always)]
    pub(crate) fn min(self, other: Self) -> Self {
        self.map2(other, |a, b| if a < b { a } else { b })
    }
    #[inline(always)]
    pub(crate) fn max(self, other: Self) -> Self {
        self.map2(other, |a, b| if a > b { a } else { b })
    }
    #[inline(always)]
    pub(crate) fn xor_sign_of(self, sign_source: Self) -> Self {
        self.map2(sign_source, |a, s| {
            f32::from_bits(a.to_bits() ^ (s.to_bits() & 0x8000_0000))
        })
    }
    #[inline(always)]
    pub(crate) fn abs(self) -> Self {
        Self(self.0.map(f32::abs))
    }
    #[inline(always)]
    pub(crate) fn lt(self, other: Self) -> Mask4 {
        self.compare(other, |a, b| a < b)
    }
    #[inline(always)]
    pub(crate) fn le(self, other: Self) -> Mask4 {
        self.compare(other, |a, b| a <= b)
    }
    #[inline(always)]
    pub(crate) fn gt(self, other: Self) -> Mask4 {
        self.compare(other, |a, b| a > b)
    }
    #[inline(always)]
    pub(crate) fn eq(self, other: Self) -> Mask4 {
        self.compare(other, |a, b| a == b)
    }
}

#[cfg(not(target_arch = "x86_64"))]
impl Mask4 {
    #[inline(always)]
    pub(crate) fn and(self, other: Self) -> Self {
        Self(std::array::from_fn(|i| self.0[i] & other.0[i]))
    }
    #[inline(always)]
    pub(crate) fn or(self, other: Self) -> Self {
        Self(std::array::from_fn(|i| self.0[i] | other.0[i]))
    }
    #[inline(always)]
    pub(crate) fn and_not(self, other: Self) -> Self {
        Self(std::array::from_fn(|i| self.0[i] & !other.0[i]))
    }
    #[inline(always)]
    pub(crate) fn bits(self) -> u32 {
        self.0
            .iter()
            .enumerate()
            .fold(0, |bits, (i, &lane)| bits | (lane as u32) << i)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(target_arch = "x86_64")]
    #[test]
    fn eight_lanes_match_scalar_arithmetic() {
        let Some(avx2) = Avx2::detect() else {
            return;
        };
        let a = [[1.5f32, -2.0, 0.0, 3.25], [7.0, -0.5, 1e-30, -4.0]];
        let b = [[0.5f32, 4.0, -1.0, 3.25], [7.0, 0.25, 2.0, -5.0]];
        let (x, y) = (F32x8::load(avx2, &a), F32x8::load(avx2, &b));
        let (a, b) = (a.as_flattened(), b.as_flattened());
        for i in 0..8 {
            assert_eq!(x.sub(y).to_array()[i], a[i] - b[i]);
            assert_eq!(x.mul(y).to_array()[i], a[i] * b[i]);
            assert_eq!(x.min(y).to_array()[i], a[i].min(b[i]));
            assert_eq!(x.max(y).to_array()[i], a[i].max(b[i]));
        }
        let expected = (0..8).fold(0, |bits, i| bits | u32::from(a[i] <= b[i]) << i);
        assert_eq!(x.le_bits(y), expected);
        assert_eq!(F32x8::splat(avx2, 2.0).to_array(), [2.0; 8]);
    }

    #[test]
    fn lanes_match_scalar_arithmetic() {
        let a = [1.5f32, -2.0, 0.0, 3.25];
        let b = [0.5f32, 4.0, -1.0, 3.25];
        let (x, y) = (F32x4::load(&a), F32x4::load(&b));
        for i in 0..4 {
            assert_eq!(x.add(y).to_array()[i], a[i] + b[i]);
            assert_eq!(x.sub(y).to_array()[i], a[i] - b[i]);
            assert_eq!(x.mul(y).to_array()[i], a[i] * b[i]);
            assert_eq!(x.div(y).to_array()[i], a[i] / b[i]);
            assert_eq!(x.min(y).to_array()[i], a[i].min(b[i]));
            assert_eq!(x.max(y).to_array()[i], a[i].max(b[i]));
            assert_eq!(x.abs().to_array()[i], a[i].abs());
            assert_eq!(
                x.xor_sign_of(y).to_array()[i],
                if b[i].is_sign_negative() { -a[i] } else { a[i] }
            );
        }
        assert_eq!(x.lt(y).bits(), 0b0010);
        assert_eq!(x.le(y).bits(), 0b1010);
        assert_eq!(x.gt(y).bits(), 0b0101);
        assert_eq!(x.eq(y).bits(), 0b1000);
        assert_eq!(x.lt(y).or(x.eq(y)).bits(), 0b1010);
        assert_eq!(x.le(y).and(x.eq(y)).bits(), 0b1000);
        assert_eq!(x.le(y).and_not(x.eq(y)).bits(), 0b0010);
        assert_eq!(F32x4::splat(2.0).to_array(), [2.0; 4]);
        let rows: [F32x4; 4] =
            std::array::from_fn(|i| F32x4::load(&std::array::from_fn(|j| (4 * i + j) as f32)));
        let columns = F32x4::transpose(rows);
        for (i, column) in columns.iter().enumerate() {
            for (j, &value) in column.to_array().iter().enumerate() {
                assert_eq!(value, (4 * j + i) as f32);
            }
        }
    }
}
