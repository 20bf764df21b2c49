//! The dense linear algebra a fit needs on its few parameters: a Cholesky solve of the damped
//! normal equations and the symmetric eigendecomposition of JᵀJ (the covariance, its
//! pseudo-inverse where the data leave a direction undetermined, and the identifiability check).
//! Matrices are n × n, row-major, n the number of free parameters (a handful).

/// x with A·x = b for a symmetric A, by Cholesky: `None` where A is not positive definite.
pub(crate) fn cholesky_solve(a: &[f64], n: usize, b: &[f64]) -> Option<Vec<f64>> {
    let mut l = a.to_vec();
    for j in 0..n {
        let mut d = l[j * n + j];
        for k in 0..j {
            d -= l[j * n + k] * l[j * n + k];
        }
        if d.is_nan() || d <= 0.0 {
            return None;
        }
        let d = d.sqrt();
        l[j * n + j] = d;
        for i in j + 1..n {
            let mut s = l[i * n + j];
            for k in 0..j {
                s -= l[i * n + k] * l[j * n + k];
            }
            l[i * n + j] = s / d;
        }
    }
    let mut y = b.to_vec();
    for i in 0..n {
        for k in 0..i {
            y[i] -= l[i * n + k] * y[k];
        }
        y[i] /= l[i * n + i];
    }
    for i in (0..n).rev() {
        for k in i + 1..n {
            y[i] -= l[k * n + i] * y[k];
        }
        y[i] /= l[i * n + i];
    }
    Some(y)
}

/// The eigenvalues (ascending) and eigenvectors (`vectors[k]` belongs to `values[k]`, unit
/// length) of a symmetric n × n matrix, by cyclic Jacobi rotations: exact to a few ulps of the
/// largest eigenvalue, which is what the smallest are compared against.
pub(crate) fn symmetric_eigen(a: &[f64], n: usize) -> (Vec<f64>, Vec<Vec<f64>>) {
    let mut m = a.to_vec();
    let mut v: Vec<f64> = (0..n * n)
        .map(|i| if i / n == i % n { 1.0 } else { 0.0 })
        .collect();
    for _sweep in 0..100 {
        let off: f64 = (0..n)
            .flat_map(|i| (0..n).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| m[i * n + j] * m[i * n + j])
            .sum();
        let scale: f64 = (0..n).map(|i| m[i * n + i] * m[i * n + i]).sum();
        if off <= f64::EPSILON * f64::EPSILON * scale || off == 0.0 {
            break;
        }
        for p in 0..n {
            for q in p + 1..n {
                rotate(&mut m, &mut v, n, p, q);
            }
        }
    }
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&i, &j| m[i * n + i].total_cmp(&m[j * n + j]));
    let values = order.iter().map(|&k| m[k * n + k]).collect();
    let vectors = order
        .iter()
        .map(|&k| (0..n).map(|i| v[i * n + k]).collect())
        .collect();
    (values, vectors)
}

/// One Jacobi rotation zeroing m[p][q], accumulated into the eigenvectors' columns `v`.
fn rotate(m: &mut [f64], v: &mut [f64], n: usize, p: usize, q: usize) {
    let apq = m[p * n + q];
    if apq == 0.0 {
        return;
    }
    let theta = (m[q * n + q] - m[p * n + p]) / (2.0 * apq);
    let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
    let t = if theta == 0.0 { 1.0 } else { t };
    let c = 1.0 / (t * t + 1.0).sqrt();
    let s = t * c;
    for k in 0..n {
        let (mkp, mkq) = (m[k * n + p], m[k * n + q]);
        m[k * n + p] = c * mkp - s * mkq;
        m[k * n + q] = s * mkp + c * mkq;
    }
    for k in 0..n {
        let (mpk, mqk) = (m[p * n + k], m[q * n + k]);
        m[p * n + k] = c * mpk - s * mqk;
        m[q * n + k] = s * mpk + c * mqk;
    }
    for k in 0..n {
        let (vkp, vkq) = (v[k * n + p], v[k * n + q]);
        v[k * n + p] = c * vkp - s * vkq;
        v[k * n + q] = s * vkp + c * vkq;
    }
}

/// AᵀA of an m × n row-major matrix, and Aᵀb.
pub(crate) fn normal_equations(a: &[f64], b: &[f64], n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut ata = vec![0.0; n * n];
    let mut atb = vec![0.0; n];
    for (row, &bi) in a.chunks_exact(n).zip(b) {
        for i in 0..n {
            atb[i] += row[i] * bi;
            for j in 0..=i {
                ata[i * n + j] += row[i] * row[j];
            }
        }
    }
    for i in 0..n {
        for j in 0..i {
            ata[j * n + i] = ata[i * n + j];
        }
    }
    (ata, atb)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_and_decomposes_a_known_matrix() {
        // A = Q diag(1, 4, 9) Qᵀ with Q a rotation: its eigenvalues are known exactly
        let (c, s) = (0.6_f64, 0.8_f64);
        let q = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]];
        let d = [1.0, 9.0, 4.0];
        let a: Vec<f64> = (0..9)
            .map(|k| (0..3).map(|m| q[k / 3][m] * d[m] * q[k % 3][m]).sum())
            .collect();
        let (values, vectors) = symmetric_eigen(&a, 3);
        for (got, want) in values.iter().zip([1.0, 4.0, 9.0]) {
            assert!((got - want).abs() < 1e-14, "{values:?}");
        }
        // the eigenvector of 9 is Q's second column, up to sign
        let dot = vectors[2][0] * q[0][1] + vectors[2][1] * q[1][1];
        assert!((dot.abs() - 1.0).abs() < 1e-14);
        let b = [1.0, 2.0, 3.0];
        let x = cholesky_solve(&a, 3, &b).unwrap();
        for i in 0..3 {
            let ax: f64 = (0..3).map(|j| a[i * 3 + j] * x[j]).sum();
            assert!((ax - b[i]).abs() < 1e-13);
        }
        assert!(cholesky_solve(&[1.0, 1.0, 1.0, 1.0], 2, &[1.0, 1.0]).is_none());
    }
}
