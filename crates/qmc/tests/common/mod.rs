//! Helpers shared by the integration tests of `qmc`.

/// True iff the `2^m` points, given by their two coordinates' digits, have exactly
/// one point in every elementary interval [a 2^-k, (a+1) 2^-k) × [b 2^-(m-k),
/// (b+1) 2^-(m-k)) for every k = 0 … m: a (0, m, 2)-net in base 2.
pub fn is_zero_m_two_net(points: &[(u32, u32)], m: u32) -> bool {
    assert_eq!(points.len(), 1 << m);
    (0..=m).all(|k| {
        let mut seen = vec![false; 1 << m];
        points.iter().all(|&(x, y)| {
            let cell_x = if k == 0 { 0 } else { (x >> (32 - k)) as usize };
            let cell_y = if k == m {
                0
            } else {
                (y >> (32 - (m - k))) as usize
            };
            !std::mem::replace(&mut seen[(cell_x << (m - k)) | cell_y], true)
        })
    })
}
