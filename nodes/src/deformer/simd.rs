//! AVX2 transposes between eight `Vec3`s as stored (`x y z x y z …`, 24 floats) and one
//! register per coordinate (x86-64 only), for the dense kernel loops: three loads and eleven
//! shuffles each way instead of 24 scalar moves, and no store-to-load forwarding stalls
//! between the transposition and the kernel.
#![cfg(target_arch = "x86_64")]

use std::arch::x86_64::*;

use glam::Vec3;

/// `[x, y, z]` of `p[0..8]`, lane `i` holding `p[i]`.
///
/// # Safety
/// The CPU must support AVX2 (AVX suffices); `p` must hold at least 8 points.
#[target_feature(enable = "avx2")]
#[inline]
pub unsafe fn load8(p: &[Vec3]) -> [__m256; 3] {
    assert!(p.len() >= 8);
    let f = p.as_ptr() as *const f32;
    // x0 y0 z0 x1 | x4 y4 z4 x5, y1 z1 x2 y2 | y5 z5 x6 y6, z2 x3 y3 z3 | z6 x7 y7 z7.
    let m03 = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(f)), _mm_loadu_ps(f.add(12)), 1);
    let m14 = _mm256_insertf128_ps(
        _mm256_castps128_ps256(_mm_loadu_ps(f.add(4))),
        _mm_loadu_ps(f.add(16)),
        1,
    );
    let m25 = _mm256_insertf128_ps(
        _mm256_castps128_ps256(_mm_loadu_ps(f.add(8))),
        _mm_loadu_ps(f.add(20)),
        1,
    );
    let xy = _mm256_shuffle_ps::<0b10_01_11_10>(m14, m25); // x2 y2 x3 y3
    let yz = _mm256_shuffle_ps::<0b01_00_10_01>(m03, m14); // y0 z0 y1 z1
    let x = _mm256_shuffle_ps::<0b10_00_11_00>(m03, xy); // x0 x1 x2 x3
    let y = _mm256_shuffle_ps::<0b11_01_10_00>(yz, xy); // y0 y1 y2 y3
    let z = _mm256_shuffle_ps::<0b11_00_11_01>(yz, m25); // z0 z1 z2 z3
    [x, y, z]
}

/// Stores `[x, y, z]` (lane `i` → `p[i]`) into `p[0..8]`: the inverse of [`load8`].
///
/// # Safety
/// The CPU must support AVX2 (AVX suffices); `p` must hold at least 8 points.
#[target_feature(enable = "avx2")]
#[inline]
pub unsafe fn store8(p: &mut [Vec3], [x, y, z]: [__m256; 3]) {
    assert!(p.len() >= 8);
    let f = p.as_mut_ptr() as *mut f32;
    let rxy = _mm256_shuffle_ps::<0b10_00_10_00>(x, y); // x0 x2 y0 y2
    let ryz = _mm256_shuffle_ps::<0b11_01_11_01>(y, z); // y1 y3 z1 z3
    let rzx = _mm256_shuffle_ps::<0b11_01_10_00>(z, x); // z0 z2 x1 x3
    let r03 = _mm256_shuffle_ps::<0b10_00_10_00>(rxy, rzx); // x0 y0 z0 x1
    let r14 = _mm256_shuffle_ps::<0b11_01_10_00>(ryz, rxy); // y1 z1 x2 y2
    let r25 = _mm256_shuffle_ps::<0b11_01_11_01>(rzx, ryz); // z2 x3 y3 z3
    _mm256_storeu_ps(f, _mm256_permute2f128_ps::<0x20>(r03, r14));
    _mm256_storeu_ps(f.add(8), _mm256_permute2f128_ps::<0x30>(r25, r03));
    _mm256_storeu_ps(f.add(16), _mm256_permute2f128_ps::<0x31>(r14, r25));
}

/// [`load8`] of `p[0..8]`, also stored as one array per coordinate (lane `i` → index
/// `i`): the registers for the envelope blend and the block for the kernel.
///
/// # Safety
/// The CPU must support AVX2 (AVX suffices); `p` must hold at least 8 points.
#[target_feature(enable = "avx2")]
#[inline]
pub unsafe fn load8_block(p: &[Vec3]) -> ([__m256; 3], [[f32; 8]; 3]) {
    let r = load8(p);
    let mut b = [[0.0f32; 8]; 3];
    for (lane, v) in b.iter_mut().zip(r) {
        _mm256_storeu_ps(lane.as_mut_ptr(), v);
    }
    (r, b)
}

/// Stores the deformed block `d` (one array per coordinate) into `p[0..8]`, blended with
/// the input points `input` (as [`load8`] gave them) by `envelope`: `input + (d −
/// input)·envelope`, the same operations as the portable loops.
///
/// # Safety
/// The CPU must support AVX2 (AVX suffices); `p` must hold at least 8 points.
#[target_feature(enable = "avx2")]
#[inline]
pub unsafe fn blend_store8(p: &mut [Vec3], d: &[[f32; 8]; 3], input: [__m256; 3], envelope: f32) {
    let r = [
        _mm256_loadu_ps(d[0].as_ptr()),
        _mm256_loadu_ps(d[1].as_ptr()),
        _mm256_loadu_ps(d[2].as_ptr()),
    ];
    blend_store8_regs(p, r, input, envelope);
}

/// [`blend_store8`] of the deformed points in registers (`r`, one per coordinate).
///
/// # Safety
/// The CPU must support AVX2 (AVX suffices); `p` must hold at least 8 points.
#[target_feature(enable = "avx2")]
#[inline]
pub unsafe fn blend_store8_regs(p: &mut [Vec3], mut r: [__m256; 3], input: [__m256; 3], envelope: f32) {
    if envelope != 1.0 {
        let env = _mm256_set1_ps(envelope);
        for (r, q) in r.iter_mut().zip(input) {
            *r = _mm256_add_ps(q, _mm256_mul_ps(_mm256_sub_ps(*r, q), env));
        }
    }
    store8(p, r);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn load_and_store_transpose_eight_points() {
        if !std::arch::is_x86_feature_detected!("avx2") {
            println!("skipped: no AVX2 on this CPU");
            return;
        }
        let p: Vec<Vec3> = (0..8)
            .map(|i| Vec3::new(i as f32, 10.0 + i as f32, 20.0 + i as f32))
            .collect();
        // SAFETY: AVX2 was checked above; `p` and `q` hold 8 points.
        let (lanes, q) = unsafe {
            let r = load8(&p);
            let mut lanes = [[0.0f32; 8]; 3];
            for (l, v) in lanes.iter_mut().zip(r) {
                _mm256_storeu_ps(l.as_mut_ptr(), v);
            }
            let mut q = vec![Vec3::ZERO; 8];
            store8(&mut q, r);
            (lanes, q)
        };
        for i in 0..8 {
            assert_eq!([lanes[0][i], lanes[1][i], lanes[2][i]], p[i].to_array(), "lane {i}");
        }
        assert_eq!(q, p);
    }
}
