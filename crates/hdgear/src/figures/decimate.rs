//! Thinning a plotted line to the points that matter.

/// Drops points a straight line through their neighbours already represents to within `tol`
/// (in y), keeping every turn of the signal: plots stay exact to a fraction of a pixel with far
/// fewer points.
///
/// From an anchor, the line to a candidate end must pass within `tol` of every point between
/// them. Each such point allows an interval of slopes through the anchor, so the points between
/// are carried as the intersection of their intervals (a "sleeve", narrowed as each point joins)
/// and a candidate is one comparison: linear time. (Checking every point between again for each
/// candidate was quadratic in the length of a straight run.) The same test as that check, rearranged; a vertical line (an end
/// straight above the anchor) asks every point between to lie within `tol` of the anchor.
///
/// ```
/// use hdgear::figures::decimate;
/// let line: Vec<(f64, f64)> = (0..100).map(|i| (f64::from(i), 2.0 * f64::from(i))).collect();
/// assert_eq!(decimate(&line, 1e-9), vec![(0.0, 0.0), (99.0, 198.0)]);
/// let corner = [(0.0, 0.0), (1.0, 1.0), (2.0, 2.0), (3.0, 0.0)];
/// assert_eq!(decimate(&corner, 1e-9), vec![(0.0, 0.0), (2.0, 2.0), (3.0, 0.0)]);
/// ```
pub fn decimate(points: &[(f64, f64)], tol: f64) -> Vec<(f64, f64)> {
    if points.len() < 3 {
        return points.to_vec();
    }
    let mut out = vec![points[0]];
    let mut anchor = 0;
    let mut sleeve = Sleeve::default();
    for i in 2..points.len() {
        let (x0, y0) = points[anchor];
        // the point before the candidate joins those between the anchor and it
        let (xj, yj) = points[i - 1];
        sleeve.narrow(xj - x0, yj - y0, tol);
        let (x1, y1) = points[i];
        if !sleeve.admits(x1 - x0, y1 - y0) {
            anchor = i - 1;
            out.push(points[anchor]);
            sleeve = Sleeve::default();
        }
    }
    out.push(*points.last().expect("non-empty"));
    out
}

/// The lines through an anchor that pass within a tolerance of some points: slopes in
/// [`lo`, `hi`], and whether every point lies within it of the anchor's height (for a vertical
/// line).
#[derive(Clone, Copy, Debug)]
struct Sleeve {
    lo: f64,
    hi: f64,
    level: bool,
}

impl Default for Sleeve {
    /// No points yet: every line.
    fn default() -> Self {
        Sleeve {
            lo: f64::NEG_INFINITY,
            hi: f64::INFINITY,
            level: true,
        }
    }
}

impl Sleeve {
    /// Adds the point (dx, dy) from the anchor: |dy − s·dx| ≤ tol. A point straight above the
    /// anchor allows every slope or none; a NaN allows none.
    fn narrow(&mut self, dx: f64, dy: f64, tol: f64) {
        let (a, b) = if dx > 0.0 {
            ((dy - tol) / dx, (dy + tol) / dx)
        } else if dx < 0.0 {
            ((dy + tol) / dx, (dy - tol) / dx)
        } else if dy.abs() <= tol {
            (f64::NEG_INFINITY, f64::INFINITY)
        } else {
            (f64::INFINITY, f64::NEG_INFINITY)
        };
        if a <= b {
            self.lo = self.lo.max(a);
            self.hi = self.hi.min(b);
        } else {
            (self.lo, self.hi) = (f64::INFINITY, f64::NEG_INFINITY);
        }
        self.level &= dy.abs() <= tol;
    }

    /// Whether the line to the end (dx, dy) from the anchor passes within the tolerance of every
    /// point added.
    fn admits(&self, dx: f64, dy: f64) -> bool {
        if dx == 0.0 {
            return self.level;
        }
        let s = dy / dx;
        self.lo <= s && s <= self.hi
    }
}
