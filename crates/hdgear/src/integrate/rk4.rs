//! The classical fourth-order Runge–Kutta step on a fixed grid: what the quasi-static sweeps
//! use to follow a state along a load or a twist (the loading branches of
//! [`crate::model::Model::branches`], the fitted loop's states and sensitivities in
//! [`crate::fit`]), where the field is smooth between grid points and its own resolution, not
//! an error estimate, sets the step.

/// One RK4 step of y' = f(t, y) from `t` by `h`, in place. `f(t, y, dy)` writes the field at
/// (t, y) into `dy` and returns false where it is undefined (a fold of a branch): then `y` is
/// left as it was and the step returns false. `scratch` holds at least 5·len(y) values.
///
/// The update is y + h/6·(k₁ + 2k₂ + 2k₃ + k₄), each stage at y + c·h·k.
pub(crate) fn rk4_step(
    f: &mut impl FnMut(f64, &[f64], &mut [f64]) -> bool,
    t: f64,
    h: f64,
    y: &mut [f64],
    scratch: &mut [f64],
) -> bool {
    let m = y.len();
    let (k1, rest) = scratch.split_at_mut(m);
    let (k2, rest) = rest.split_at_mut(m);
    let (k3, rest) = rest.split_at_mut(m);
    let (k4, rest) = rest.split_at_mut(m);
    let at = &mut rest[..m];
    let stage = |at: &mut [f64], k: &[f64], c: f64| {
        for ((a, y), k) in at.iter_mut().zip(y.iter()).zip(k) {
            *a = y + c * h * k;
        }
    };
    if !f(t, y, k1) {
        return false;
    }
    stage(at, k1, 0.5);
    if !f(t + 0.5 * h, at, k2) {
        return false;
    }
    stage(at, k2, 0.5);
    if !f(t + 0.5 * h, at, k3) {
        return false;
    }
    stage(at, k3, 1.0);
    if !f(t + h, at, k4) {
        return false;
    }
    for j in 0..m {
        y[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
    }
    true
}

#[cfg(test)]
mod tests {
    use super::rk4_step;

    /// On y' = t·y (y = exp(t²/2)) the global error over [0, 1] falls 16-fold per halved step:
    /// fourth order, against the closed form.
    #[test]
    fn rk4_is_fourth_order_against_a_closed_form() {
        let error = |n: usize| {
            let (mut y, mut scratch) = ([1.0], [0.0; 5]);
            let h = 1.0 / n as f64;
            for i in 0..n {
                let mut f = |t: f64, y: &[f64], dy: &mut [f64]| {
                    dy[0] = t * y[0];
                    true
                };
                assert!(rk4_step(&mut f, i as f64 * h, h, &mut y, &mut scratch));
            }
            (y[0] - 0.5f64.exp()).abs()
        };
        let ratio = error(40) / error(80);
        assert!((ratio - 16.0).abs() < 0.5, "{ratio}");
    }

    /// A field undefined at a stage leaves the state as it was.
    #[test]
    fn an_undefined_field_leaves_the_state() {
        let (mut y, mut scratch) = ([2.0, 3.0], [0.0; 10]);
        let mut calls = 0;
        let mut f = |_: f64, _: &[f64], dy: &mut [f64]| {
            calls += 1;
            dy.fill(1.0);
            calls < 3
        };
        assert!(!rk4_step(&mut f, 0.0, 0.1, &mut y, &mut scratch));
        assert_eq!(y, [2.0, 3.0]);
    }
}
