//! numpy's `A @ x` for a C-contiguous float64 matrix `A` (`rows × n`) and a contiguous float64
//! vector `x`, as numpy 2.4.6 with its bundled OpenBLAS 0.3.31 (scipy-openblas, `DYNAMIC_ARCH`)
//! computes it under each of the kernels in [`Kernel`].
//!
//! Written by hand for the same reason as `openblas.rs`: the last bit depends on how the kernel
//! splits each row into partial sums and on where its compiler fused multiply-adds. The path,
//! read from numpy's `matmul.c.src` and OpenBLAS's `interface/gemv.c` and
//! `kernel/x86_64/dgemv_t_4.c` (+ `dgemv_t_microk_haswell-4.c`), and confirmed in the wheel's
//! machine code (`dgemv_t_PRESCOTT` .. `dgemv_t_SKYLAKEX`):
//!
//! * `n == 0`: numpy's own loop writes `+0.0`. `rows == 1`: numpy's `DOUBLE_dot`, i.e.
//!   `0.0 + cblas_ddot` ([`openblas::ddot`]). `n == 1` (and `rows ≥ 2`): numpy's own loop,
//!   `0.0 + a·x`.
//! * Otherwise `cblas_dgemv(ColMajor, Trans, n, rows, 1.0, A, lda = n, x, 1, 0.0, y, 1)`:
//!   `y` is zeroed (the `beta = 0` scal), then OpenBLAS's `dgemv_t` runs with its `m = n` and its
//!   `n = rows`. All five kernels use `dgemv_t_4.c`; they differ only in the 4-row block (a
//!   4-lane FMA microkernel on Haswell/SkylakeX, plain C elsewhere) and in the element tail,
//!   which the Haswell/SkylakeX builds contract into FMAs. The first `n & !3` elements of each
//!   row (in passes of at most 2048) go through 4-row blocks, then a 2-row and a 1-row SSE2
//!   kernel, each with its own lane split; their sums are added to `y`. The last `n & 3`
//!   elements are then added to each `y[i]` by scalar code.
//!
//! So `rows == 3` takes a different path from `rows == 4`: rows 0 and 1 go through the 2-row
//! kernel and row 2 through the 1-row kernel (the same SSE2 code under every kernel), whereas
//! 4 rows go through the 4-row block.
//!
//! Checked bit for bit against the live library under every `OPENBLAS_CORETYPE` (Prescott,
//! Nehalem, Sandybridge, Haswell, SkylakeX) on an AVX-512 machine: about 19 000 random
//! matrices (mixed magnitudes, sparse Jacobian-like rows, signed zeros, cancellation-heavy
//! values), `n = 1..=130` and `2040..=2060, 4096..=4099, 6150, 6151`, `rows = 1..=9, 13, 15,
//! 16` (mostly 3), all equal. With NaN or infinite inputs everything matches except that a
//! NaN result's sign bit may differ. The tests below hold a sample of those cases.
//! Valid while `rows · n` stays under OpenBLAS's single-thread limit for gemv
//! (`115200 · GEMM_MULTITHREAD_THRESHOLD`, 460 800 with the default threshold of 4), and for
//! `n ≤ 10 000` when `rows == 1` (the `ddot` limit).

use super::openblas::{self, Kernel};

/// `dgemv_t_4.c`'s `NBMAX`: at most this many elements of each row are summed per pass.
const NBMAX: usize = 2048;

/// `y[i] = Σ_j a[i·n + j] · x[j]` for `i < rows`, as numpy's `a.reshape(rows, n) @ x` computes it
/// under `kernel` (see the module docs). Allocation-free. `a` must hold `rows · n` values, `x`
/// `n` and `y` at least `rows`; only `y[..rows]` is written.
pub fn dgemv_t(kernel: Kernel, rows: usize, n: usize, a: &[f64], x: &[f64], y: &mut [f64]) {
    assert!(
        a.len() >= rows * n && x.len() >= n && y.len() >= rows,
        "dgemv_t: slices too short for {rows} x {n}"
    );
    let y = &mut y[..rows];
    if rows == 0 {
        return;
    }
    if n == 0 {
        y.fill(0.0);
        return;
    }
    if rows == 1 {
        // matmul's `scalar_out` case: DOUBLE_dot, `sum = 0.; sum += cblas_ddot(..)`.
        y[0] = 0.0 + openblas::ddot(kernel, n, &|j| a[j], &|j| x[j]);
        return;
    }
    if n == 1 {
        // matmul's `scalar_vec` case: `*op = 0; *op += val1 * val2`.
        for (yi, ai) in y.iter_mut().zip(a) {
            *yi = 0.0 + *ai * x[0];
        }
        return;
    }

    let fused = matches!(kernel, Kernel::Haswell | Kernel::SkylakeX);
    // `beta = 0`: interface/gemv.c scales y by zero first.
    y.fill(0.0);

    let m3 = n & 3;
    let body = n - m3;
    let mut start = 0;
    while start < body {
        let nb = (body - start).min(NBMAX);
        let row = |i: usize| &a[i * n + start..i * n + start + nb];
        let xs = &x[start..start + nb];
        // Groups of four rows; each sum is added by add_y: `y += t * alpha` (alpha = 1).
        let full = rows & !3;
        for (r, yr) in y[..full].iter_mut().enumerate() {
            *yr += block4_row(fused, row(r), xs);
        }
        let mut r = full;
        if rows - r >= 2 {
            y[r] += block2_row(row(r), xs);
            y[r + 1] += block2_row(row(r + 1), xs);
            r += 2;
        }
        if r < rows {
            y[r] += block1_row(row(r), xs);
        }
        start += nb;
    }

    if m3 == 0 {
        return;
    }
    // The scalar tail: `y[i] += a0*x0 + a1*x1 + a2*x2` (xtemp = x * alpha = x). The FMA builds
    // compute the sum as fma(a2, x2, fma(a0, x0, a1*x1)) and, for a single element, fuse the
    // update itself: y = fma(a0, x0, y).
    let xs = &x[body..n];
    for (r, yr) in y.iter_mut().enumerate() {
        let p = &a[r * n + body..r * n + n];
        *yr = match (m3, fused) {
            (1, false) => *yr + p[0] * xs[0],
            (1, true) => p[0].mul_add(xs[0], *yr),
            (2, false) => *yr + (p[0] * xs[0] + p[1] * xs[1]),
            (2, true) => *yr + p[0].mul_add(xs[0], p[1] * xs[1]),
            (_, false) => *yr + ((p[0] * xs[0] + p[1] * xs[1]) + p[2] * xs[2]),
            (_, true) => *yr + p[2].mul_add(xs[2], p[0].mul_add(xs[0], p[1] * xs[1])),
        };
    }
}

/// One row of `dgemv_kernel_4x4` over `a.len()` (a multiple of 4) elements.
///
/// Haswell/SkylakeX (`dgemv_t_microk_haswell-4.c`): one 4-lane accumulator, lane `l` fusing in
/// elements `l, l+4, ..`, folded as `(l0 + l2) + (l1 + l3)`. Elsewhere (plain C):
/// `temp += a0*x0 + a1*x1 + a2*x2 + a3*x3` per group of four, left to right.
fn block4_row(fused: bool, a: &[f64], x: &[f64]) -> f64 {
    if fused {
        let mut acc = [0.0f64; 4];
        for (ac, xc) in a.chunks_exact(4).zip(x.chunks_exact(4)) {
            for l in 0..4 {
                acc[l] = ac[l].mul_add(xc[l], acc[l]);
            }
        }
        (acc[0] + acc[2]) + (acc[1] + acc[3])
    } else {
        let mut temp = 0.0f64;
        for (ac, xc) in a.chunks_exact(4).zip(x.chunks_exact(4)) {
            temp += ((ac[0] * xc[0] + ac[1] * xc[1]) + ac[2] * xc[2]) + ac[3] * xc[3];
        }
        temp
    }
}

/// One row of `dgemv_kernel_4x2` (SSE2 inline assembly, every kernel): a 2-lane accumulator,
/// lane `l` adding the products of elements `l, l+2, ..` (multiply, then add), then
/// `lane0 + lane1`.
fn block2_row(a: &[f64], x: &[f64]) -> f64 {
    let mut acc = [0.0f64; 2];
    for (ac, xc) in a.chunks_exact(2).zip(x.chunks_exact(2)) {
        acc[0] += ac[0] * xc[0];
        acc[1] += ac[1] * xc[1];
    }
    acc[0] + acc[1]
}

/// `dgemv_kernel_4x1` (SSE2 inline assembly, every kernel): two 2-lane accumulators, one taking
/// elements `4k, 4k+1` and the other `4k+2, 4k+3`; then `(A0 + B0) + (A1 + B1)`.
fn block1_row(a: &[f64], x: &[f64]) -> f64 {
    let mut p = [0.0f64; 2];
    let mut q = [0.0f64; 2];
    for (ac, xc) in a.chunks_exact(4).zip(x.chunks_exact(4)) {
        p[0] += ac[0] * xc[0];
        p[1] += ac[1] * xc[1];
        q[0] += ac[2] * xc[2];
        q[1] += ac[3] * xc[3];
    }
    (p[0] + q[0]) + (p[1] + q[1])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One `a.reshape(rows, n) @ x` and numpy's result bits under each kernel, in
    /// [`Kernel::ALL`] order (recorded with `OPENBLAS_CORETYPE` set to each name).
    struct Case {
        rows: usize,
        n: usize,
        a: &'static [f64],
        x: &'static [f64],
        want: [&'static [u64]; 5],
    }

    // Picked from the recorded cases to tell the kernels apart: rows = 3 with every tail length
    // (n % 4 = 1, 2, 3), the 4-row block (rows = 4), 4 + 2 + 1 rows (rows = 7), the ddot path
    // (rows = 1), and n = 1 with a -0.0 product (numpy's `0 + a*x` gives +0.0).
    #[rustfmt::skip]
    const CASES: &[Case] = &[
        Case {
            rows: 3,
            n: 2,
            a: &[0.903769233544611, 1.0353876612481925, 0.4589212381579702, -1.8077607189745102, 0.14763281445712698, 0.21550250905222273],
            x: &[-0.6289625382074258, 0.1779890455938724],
            want: [
                &[0xbfd895e711ae1154, 0xbfe38871e5184f72, 0xbfabe737a7c2bfd2], // Prescott
                &[0xbfd895e711ae1154, 0xbfe38871e5184f72, 0xbfabe737a7c2bfd2], // Nehalem
                &[0xbfd895e711ae1154, 0xbfe38871e5184f72, 0xbfabe737a7c2bfd2], // Sandybridge
                &[0xbfd895e711ae1155, 0xbfe38871e5184f73, 0xbfabe737a7c2bfd2], // Haswell
                &[0xbfd895e711ae1155, 0xbfe38871e5184f73, 0xbfabe737a7c2bfd2], // SkylakeX
            ],
        },
        Case {
            rows: 3,
            n: 3,
            a: &[-0.06091148606276109, -0.6828359556074766, 0.37745489585246617, 0.8623127973991591, -0.6650106416958981, -0.33257225166056803, -0.5039385555410332, 0.08078190620866921, -0.867206892131017],
            x: &[0.6386438745275602, -0.866149629865082, -2.41206439600695],
            want: [
                &[0xbfd6e7f798a37edc, 0x3ffedcc1351b0ff2, 0x3ffb330143f349eb], // Prescott
                &[0xbfd6e7f798a37edc, 0x3ffedcc1351b0ff2, 0x3ffb330143f349eb], // Nehalem
                &[0xbfd6e7f798a37edc, 0x3ffedcc1351b0ff2, 0x3ffb330143f349eb], // Sandybridge
                &[0xbfd6e7f798a37edd, 0x3ffedcc1351b0ff1, 0x3ffb330143f349eb], // Haswell
                &[0xbfd6e7f798a37edd, 0x3ffedcc1351b0ff1, 0x3ffb330143f349eb], // SkylakeX
            ],
        },
        Case {
            rows: 3,
            n: 5,
            a: &[3.324256586871518, 3.2696778982154006e-07, -3.267860067234238e-07, -141768.2785456951, -0.007375018339023121, -8.91188794043179e-08, -1.8583372077414506e-07, -1.8523013751266375, 2.6132596005158556e-05, 191.08077056122858, -54380028.164537124, -176380.87047028574, -21065.175274167686, 58370.4311737595, -147.38817338487192],
            x: &[-0.7742442638846704, -0.8333370273632016, 1.0605011453061222, 1.2040231546916935, 0.6131116903806554],
            want: [
                &[0xc104d636f23c1d48, 0x405ccc2110edda74, 0x41842b5c976f431d], // Prescott
                &[0xc104d636f23c1d48, 0x405ccc2110edda74, 0x41842b5c976f431d], // Nehalem
                &[0xc104d636f23c1d48, 0x405ccc2110edda74, 0x41842b5c976f431d], // Sandybridge
                &[0xc104d636f23c1d48, 0x405ccc2110edda75, 0x41842b5c976f431d], // Haswell
                &[0xc104d636f23c1d48, 0x405ccc2110edda75, 0x41842b5c976f431d], // SkylakeX
            ],
        },
        Case {
            rows: 3,
            n: 6,
            a: &[-0.5691801510720262, -0.45840816908718296, -0.02172224775573668, -0.3117869667166863, 0.7276696292807353, -0.6354877448783557, 0.5146159888096877, -0.6491683652721795, 0.40834880629566894, -0.10430935132606657, 0.7163003656854867, 2.3482734068648496, -0.015647038029682304, 0.63518526023547, -1.019378817746839, -0.5333318894079413, 0.27083180532966833, 1.1516273185129957],
            x: &[-1.1913710957593047, -0.25204180515984254, 1.240564831949038, -1.81666893517363, 0.438896713053256, -0.30083617745442426],
            want: [
                &[0x3ffd7f9fb1a4853d, 0xbfc29ea197ac3e5a, 0xbfe545a9cc8fb985], // Prescott
                &[0x3ffd7f9fb1a4853d, 0xbfc29ea197ac3e5a, 0xbfe545a9cc8fb985], // Nehalem
                &[0x3ffd7f9fb1a4853d, 0xbfc29ea197ac3e5a, 0xbfe545a9cc8fb985], // Sandybridge
                &[0x3ffd7f9fb1a4853c, 0xbfc29ea197ac3e5a, 0xbfe545a9cc8fb985], // Haswell
                &[0x3ffd7f9fb1a4853c, 0xbfc29ea197ac3e5a, 0xbfe545a9cc8fb985], // SkylakeX
            ],
        },
        Case {
            rows: 3,
            n: 7,
            a: &[-0.8144156355335442, 0.7992102162920421, 0.5642241587301136, -1.9969328111370805, -2.355198546150289, 0.10925436630760295, 0.0006290551250335088, -2.151198282153648, 0.22025333720913456, 0.12251517883167465, -1.7472249525187826, -0.5147447586425985, 1.172945375528864, -0.3564446840939468, -1.0315789213425253, -0.2631137341469463, 1.8708789368844692, -1.7467952867314016, 0.07067946958526555, 0.6769140471362294, 0.903273668613524],
            x: &[1.5085001285086477, -1.7477058487412818, 1.4250331863552568, 1.3957846339684346, 0.3251649300926011, -0.4419130795435182, -1.2540634549545493],
            want: [
                &[0xc015b1a4465f864c, 0xc0188815a5336a34, 0xc00237e5ff6977fc], // Prescott
                &[0xc015b1a4465f864c, 0xc0188815a5336a34, 0xc00237e5ff6977fc], // Nehalem
                &[0xc015b1a4465f864c, 0xc0188815a5336a34, 0xc00237e5ff6977fc], // Sandybridge
                &[0xc015b1a4465f864c, 0xc0188815a5336a34, 0xc00237e5ff6977fd], // Haswell
                &[0xc015b1a4465f864c, 0xc0188815a5336a34, 0xc00237e5ff6977fd], // SkylakeX
            ],
        },
        Case {
            rows: 3,
            n: 11,
            a: &[1.2344229861908353, -1.9024558219494552, 0.7914910825450577, 0.5314438543326587, -1.0254155491113703, 1.0097255023289675, -0.41402605461103564, 1.5110232293007004, -1.6605908238457188, 0.7518180175585017, -0.4312481001526268, 1.0799071990262832, 0.8568058782015441, 0.5211112059098277, 0.39502508087728594, 1.2340127539421732, -0.3918916300316137, 0.1716341227483642, 1.908284489323087, 0.3700824756163322, -0.668421810210369, 0.0705177938994892, 1.481131903647165, -0.6568600160348701, 0.05334882651342861, 0.24363308595778818, -0.26977010577220734, 0.3236535568402523, -0.46828820406839744, 1.9056583888134193, 0.12375364684746588, 0.9767200069580965, -0.20468066473267527],
            x: &[2.0, 0.0, 5.0, -4.123999671068532e-18, 0.0, 5.0, -2.0, -5.0, -5.0, -3.0, 1.138204053907918e-17],
            want: [
                &[0x4025973a12534ff9, 0xc01bb2197d78fc53, 0xc01d2c68adb57722], // Prescott
                &[0x4025973a12534ff9, 0xc01bb2197d78fc53, 0xc01d2c68adb57722], // Nehalem
                &[0x4025973a12534ff9, 0xc01bb2197d78fc53, 0xc01d2c68adb57722], // Sandybridge
                &[0x4025973a12534ff8, 0xc01bb2197d78fc53, 0xc01d2c68adb57722], // Haswell
                &[0x4025973a12534ff8, 0xc01bb2197d78fc53, 0xc01d2c68adb57722], // SkylakeX
            ],
        },
        Case {
            rows: 3,
            n: 18,
            a: &[-0.9876891564186467, 0.1461913278446454, 0.8893557526883713, 0.0, -0.9832007756566024, 0.15911753472449996, -0.7268489479968165, 0.34055074410053177, 0.0, 0.0, 0.6466545441082736, 0.08633110325466054, 0.041746539937038696, -0.9582359725528464, -0.25439482860742957, -0.9083798082616923, 0.753123274986238, 0.2261593458504445, 0.0, -0.12117012750857836, 0.8521976679515175, -0.0, -0.881606277538916, 0.2792519979234953, -0.0, 0.7796952325747271, 0.8272404848271375, -0.29853885938304314, 0.9329049444364808, -0.37357952590577126, -0.0, -0.8637321205679995, 0.09812016891865394, -0.0, -0.0, -0.27664265142422795, 0.4564432364052826, 0.0, 0.5671170481490511, 0.13361512400940145, 0.40543561126222527, -0.503480834860462, 0.0, 0.11367127610754268, 0.0, 0.8266775280967089, 0.0, 0.07646840888140116, -0.5202494183146198, 0.9761485383844624, 0.8573752076962615, 0.0, -0.8171027896783609, 0.5358756270999627],
            x: &[-1.4920133731007545, 1.8642476100238001, -0.7251726279301015, 0.30456618865728496, 0.09837650555491156, -0.466510219736856, 2.1379341433044483, 0.1610473675066684, 2.4030101422519676, 2.155934452659671, 0.3615825275695434, -0.8552985637767275, -0.1607896223411552, 0.8355917895065917, 1.7167315771759788, -0.17775281325248476, 1.5718712550777807, 0.0013771743875724538],
            want: [
                &[0xbfd3ac21a2540b54, 0x3fe063235f08d571, 0x40005e0120178f5e], // Prescott
                &[0xbfd3ac21a2540b54, 0x3fe063235f08d571, 0x40005e0120178f5e], // Nehalem
                &[0xbfd3ac21a2540b54, 0x3fe063235f08d571, 0x40005e0120178f5e], // Sandybridge
                &[0xbfd3ac21a2540b58, 0x3fe063235f08d571, 0x40005e0120178f5e], // Haswell
                &[0xbfd3ac21a2540b58, 0x3fe063235f08d571, 0x40005e0120178f5e], // SkylakeX
            ],
        },
        Case {
            rows: 3,
            n: 27,
            a: &[0.0, -1.4180025386598154, -0.6312323112139794, -0.8880687100888058, -1.1367388086392378, -0.8671427420767008, 1.1026258504237574e+16, -9998031382139310.0, 1.349274539228445e+16, -7062995980524729.0, 1.9235963207826312, 0.0, -5899803796879753.0, -0.6695489912609145, 0.0, -0.8473678651609531, 1.3939908683796828e+16, 5236629709962544.0, 3.5253728193373335, -1.0108484334876162e+16, 2.80296620934388, 6093869932275270.0, 1.2830165022598004, -7467072606401878.0, 1.7209585047542841, -1.3332314598953606e+16, 0.581047623968103, 0.0013930063414369289, 8531383035859162.0, 3.1924299169235955, 3.6387164159437133, 1.3495820336493733, 4.153747287852416, 0.0012785974022497808, 1.3699128891166304e+16, 9578121937102490.0, 2.435494281376119, 1.1234225240535802e+16, 0.0, 1.7886964520360555, 0.0, 2.6030007892940206, -0.9949658589604291, 2.800599782983553, 1.1430681210092408, -9811513975743986.0, 0.0, 1.4400504637533038e+16, 0.0, 0.0011717277611179632, 0.0, 1.039596342544792e+16, 1.389851559320508, -0.6079385343181729, -1.3286525475188642e+16, 5574965817035507.0, -1.0552841637621384, 1.418812273288587, 0.6543305440457943, 1.2456193645612736, 9106238563025742.0, 0.0, 7107017155343581.0, 0.6659880511323713, -0.8263857201161374, -1.0450032324876112e+16, 0.0012963724702010357, 5479644510134892.0, 0.0005973013624548328, 0.9230015471952681, 0.001444053693691514, 3.2433534547800997, 0.0, 0.0, -1.283940064815182, 0.0, 1.4522348534899359, -9106007714121228.0, 0.0006703866231257543, -1.2352082565612888e+16, -1.131215048701691e+16],
            x: &[-0.7431703786627943, 0.05397163446145419, -0.15766705080696383, 0.7368676548985118, 0.6515011381939179, 0.24850239311676933, 1.150452359285584, -2.0171584997830907, -0.24684450857171192, 1.2945235298255868, 0.3187859168555019, 1.4180861345905555, 0.5297091078675153, -0.886864216181095, -1.0988842416910038, -1.748768877008369, -1.6604017109524376, -0.6775169486686315, -1.5359444942694436, -0.21103281874001836, -0.47398400542843433, -0.6026005775322412, 0.9695913956572725, -0.11728855602314521, 0.28243915133610387, 0.3963958369644137, 0.9733589230657528],
            want: [
                &[0xc34b55a473d9057e, 0xc34a3f06e6196477, 0xc34bbf850eaf639e], // Prescott
                &[0xc34b55a473d9057e, 0xc34a3f06e6196477, 0xc34bbf850eaf639e], // Nehalem
                &[0xc34b55a473d9057e, 0xc34a3f06e6196477, 0xc34bbf850eaf639e], // Sandybridge
                &[0xc34b55a473d9057e, 0xc34a3f06e6196477, 0xc34bbf850eaf639f], // Haswell
                &[0xc34b55a473d9057e, 0xc34a3f06e6196477, 0xc34bbf850eaf639f], // SkylakeX
            ],
        },
        Case {
            rows: 4,
            n: 10,
            a: &[-2.1671056805195983, -23043425.19659903, 0.002423103707484407, -0.009547050239514812, 291184.9612832885, 0.4183919079726945, 0.0001653228830407014, 67.15749512437431, 0.19043523900791048, -15.4924728245908, 27.68572002364185, -0.03618869186975344, 0.01102270249451308, -0.01098446296623945, -0.000531789395169922, -10132876.292505473, 177.96768851426398, -3.5910135320744824e-05, -688344.1794458545, -0.10100331872849398, -1.530852211736736, 1.7488481213556708e-08, -0.13863324864139706, 74878.96338056582, -3.8535979026138855e-05, 0.017765085324784696, 1101618.518233756, -4901365.87733196, 0.32363747807844545, -46208.59413119539, 1.9385592094485793e-07, 0.08069192188105347, -0.0006010916952756549, -7.87454406784855e-05, -2.7195094293215587e-07, -9828.724526408385, 0.0003463735545665914, 3.0207803328566094e-08, -2.4424600229496385e-07, 1.1029545252302285e-05],
            x: &[0.2360481310801393, -1.215032179415172, 1.390830570262782, 0.3532834077982466, 1.9069966509679097, -2.209568103951454, -0.6860772407194381, -0.5204629458875196, 1.2872544795079814, -1.3211235260566025],
            want: [
                &[0x417b3b230351117e, 0x417481c72c091367, 0x413cba3c8264acb0, 0x40d53548c5864d89], // Prescott
                &[0x417b3b230351117e, 0x417481c72c091367, 0x413cba3c8264acb0, 0x40d53548c5864d89], // Nehalem
                &[0x417b3b230351117e, 0x417481c72c091367, 0x413cba3c8264acb0, 0x40d53548c5864d89], // Sandybridge
                &[0x417b3b230351117f, 0x417481c72c091368, 0x413cba3c8264acaf, 0x40d53548c5864d88], // Haswell
                &[0x417b3b230351117f, 0x417481c72c091368, 0x413cba3c8264acaf, 0x40d53548c5864d88], // SkylakeX
            ],
        },
        Case {
            rows: 7,
            n: 9,
            a: &[0.0, 6772766612961204.0, 0.0, 0.0, 0.5815830515518498, 0.8996524820576459, 0.0011183817372933036, -5691643084817321.0, 0.0013895396360262056, 1.5440296808187746, 0.9233760801672972, 2.854029322985105, 0.0, 0.6950198278087667, 0.0, 0.9345979915241497, -1.327567684761942e+16, 7640950737047781.0, 0.001256324633544859, -1.1385656624802944, 9470364607936896.0, 0.8482204962072066, 0.5356474332307448, 0.0, 1.1918719294908802e+16, -0.7087923537859487, 5811937341517861.0, 6071178457757329.0, 0.598270745822183, 7732615873953435.0, -8737760811596147.0, 0.0, 1.3195312443327804e+16, 1.1135618864694424e+16, 0.0005525212105915831, 0.0, -6060848276926282.0, 5075474738651216.0, 0.0007809212842293002, -0.9782567160476824, -0.9434190336949252, 0.0007894602783188627, 1.2486239204353202e+16, 0.0, 0.0005554074405055438, 0.0005158317639567604, 0.0, 0.0009059063674889531, 3.5878598301070035, 0.0007597193304195486, -1.385747002638995, 0.0, -6102776285518168.0, 0.0, 1.6148730336202783, 0.9939408822706216, 0.0, 0.0012403011208859873, 8533942643128184.0, 0.001053406293478505, 0.000510757179631488, 0.0007119034050283909, 1.2740327694496388e+16],
            x: &[0.00893403747589981, 2.912385030760888, 0.9094967125623206, 0.6930057744114159, 1.598484743164938, 0.6662547513466921, 0.6586854012571451, -1.126853803144789, 0.573685253428353],
            want: [
                &[0x4357373812e70df2, 0x43512e253410de3a, 0x435195956f70a648, 0x434e7a9058148916, 0x435462b39aea599a, 0x43386e89972f1d5a, 0x43529b8cd865c098], // Prescott
                &[0x4357373812e70df2, 0x43512e253410de3a, 0x435195956f70a648, 0x434e7a9058148916, 0x435462b39aea599a, 0x43386e89972f1d5a, 0x43529b8cd865c098], // Nehalem
                &[0x4357373812e70df2, 0x43512e253410de3a, 0x435195956f70a648, 0x434e7a9058148916, 0x435462b39aea599a, 0x43386e89972f1d5a, 0x43529b8cd865c098], // Sandybridge
                &[0x4357373812e70df1, 0x43512e253410de39, 0x435195956f70a647, 0x434e7a9058148916, 0x435462b39aea599a, 0x43386e89972f1d5a, 0x43529b8cd865c098], // Haswell
                &[0x4357373812e70df1, 0x43512e253410de39, 0x435195956f70a647, 0x434e7a9058148916, 0x435462b39aea599a, 0x43386e89972f1d5a, 0x43529b8cd865c098], // SkylakeX
            ],
        },
        Case {
            rows: 1,
            n: 13,
            a: &[0.9294612191872743, 0.7604834080742057, -0.772152280007556, -1.4768849326484936, -0.8703444169578818, -1.7789066750029292, 0.9075633443026456, -0.10485072073148849, -0.6661457183714177, 0.7448292311006487, 0.9915156063981473, 0.7795337153366962, 0.4731462448108774],
            x: &[0.05086979772132653, 1.5076906906336298, 0.19966873054753398, -0.7916143111867009, 0.4238756789240946, -0.26595379658937507, -1.4833352596342486, -1.5950982018999222, 0.7946587038510297, 0.42365787248694015, -0.045315181141944764, -0.1553397222498674, -0.3681339275450149],
            want: [
                &[0x3fe28f6fafef2ce0], // Prescott
                &[0x3fe28f6fafef2ce1], // Nehalem
                &[0x3fe28f6fafef2ce1], // Sandybridge
                &[0x3fe28f6fafef2ce1], // Haswell
                &[0x3fe28f6fafef2ce2], // SkylakeX
            ],
        },
        Case {
            rows: 3,
            n: 1,
            a: &[0.0, -158.24965697285236, 0.0],
            x: &[-0.29969851529910546],
            want: [
                &[0x0000000000000000, 0x4047b6ae124f728f, 0x0000000000000000], // Prescott
                &[0x0000000000000000, 0x4047b6ae124f728f, 0x0000000000000000], // Nehalem
                &[0x0000000000000000, 0x4047b6ae124f728f, 0x0000000000000000], // Sandybridge
                &[0x0000000000000000, 0x4047b6ae124f728f, 0x0000000000000000], // Haswell
                &[0x0000000000000000, 0x4047b6ae124f728f, 0x0000000000000000], // SkylakeX
            ],
        },
    ];

    #[test]
    fn matches_numpy_under_every_kernel() {
        for (c, case) in CASES.iter().enumerate() {
            for (kernel, want) in Kernel::ALL.into_iter().zip(case.want) {
                let mut y = [f64::NAN; 8];
                dgemv_t(kernel, case.rows, case.n, case.a, case.x, &mut y);
                let got: Vec<u64> = y[..case.rows].iter().map(|v| v.to_bits()).collect();
                assert_eq!(
                    got, want,
                    "case {c} ({} x {}) under {kernel:?}",
                    case.rows, case.n
                );
            }
        }
    }

    #[test]
    fn empty_shapes() {
        let mut y = [f64::NAN; 3];
        dgemv_t(Kernel::Haswell, 3, 0, &[], &[], &mut y);
        assert!(y.iter().all(|v| v.to_bits() == 0));
        dgemv_t(Kernel::Haswell, 0, 4, &[], &[1.0; 4], &mut []);
    }
}
