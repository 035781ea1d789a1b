//! The sRGB transfer function (IEC 61966-2-1): the piecewise curve that
//! maps linear light to the encoded values of 8-bit images and back.

/// Encodes a linear value in `[0, 1]` with the sRGB transfer function:
/// `12.92 x` below `0.0031308`, `1.055 x^(1/2.4) − 0.055` above
/// (IEC 61966-2-1). Values outside `[0, 1]` are not clamped here.
pub fn linear_to_srgb(linear: f32) -> f32 {
    if linear <= 0.003_130_8 {
        12.92 * linear
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

/// Decodes an sRGB-encoded value in `[0, 1]` to linear light: `x / 12.92`
/// up to `0.04045`, `((x + 0.055) / 1.055)^2.4` above (IEC 61966-2-1).
pub fn srgb_to_linear(encoded: f32) -> f32 {
    if encoded <= 0.040_45 {
        encoded / 12.92
    } else {
        ((encoded + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transfer_functions_are_inverse_and_continuous() {
        for step in 0..=1000 {
            let value = step as f32 / 1000.0;
            let round_trip = srgb_to_linear(linear_to_srgb(value));
            assert!((round_trip - value).abs() < 1e-6, "{value} -> {round_trip}");
        }
        // Both pieces meet at the threshold (to the precision of the
        // standard's rounded constants).
        let below = 12.92 * 0.003_130_8f32;
        let above = 1.055 * 0.003_130_8f32.powf(1.0 / 2.4) - 0.055;
        assert!((below - above).abs() < 1e-6);
        assert!((linear_to_srgb(1.0) - 1.0).abs() < 1e-6);
    }
}
