//! Adaptive refinement of a verdict map on a rectangular grid: the cells of a coarse lattice are
//! computed, and a block of the lattice is split, its midpoints computed, wherever two computed
//! cells in it disagree, down to single cells. A cell left uncomputed lies in a block whose every
//! computed cell (its corners and whatever its neighbours' refinement computed on its edges)
//! agrees, and takes that common value.
//!
//! The assumption, stated: a region of one verdict narrower than the lattice spacing that lies
//! wholly inside a block, touching none of its computed cells, is missed. A spacing of 1 computes
//! every cell.
//!
//! ```
//! use hdgear::refine::refine;
//! // a verdict that changes along one line of a 40 × 40 grid
//! let verdict = |(i, j): (usize, usize)| i + 2 * j < 50;
//! let map = refine(40, 40, 8, |cells| {
//!     Ok::<_, ()>(cells.iter().map(|&c| verdict(c)).collect())
//! })
//! .unwrap();
//! assert!((0..40 * 40).all(|k| map.values[k] == verdict((k / 40, k % 40))));
//! assert!(map.computed.iter().filter(|&&c| c).count() < 40 * 40 / 2);
//! ```

/// A refined map, row-major (`rows` × `cols`).
#[derive(Clone, Debug, PartialEq)]
pub struct Refined<V> {
    /// The value of every cell.
    pub values: Vec<V>,
    /// Whether a cell was computed (false: it took the common value of its block).
    pub computed: Vec<bool>,
}

/// A block of the grid: rows `r.0..=r.1`, columns `c.0..=c.1`.
#[derive(Clone, Copy)]
struct Block {
    r: (usize, usize),
    c: (usize, usize),
}

impl Block {
    fn cells(self) -> impl Iterator<Item = (usize, usize)> {
        (self.r.0..=self.r.1).flat_map(move |i| (self.c.0..=self.c.1).map(move |j| (i, j)))
    }

    /// The block's four quarters (halves, or itself, along an axis too short to split).
    fn split(self) -> Vec<Block> {
        let halves = |(a, b): (usize, usize)| {
            if b - a >= 2 {
                let m = (a + b) / 2;
                vec![(a, m), (m, b)]
            } else {
                vec![(a, b)]
            }
        };
        let cols = halves(self.c);
        halves(self.r)
            .into_iter()
            .flat_map(|r| cols.iter().map(move |&c| Block { r, c }))
            .collect()
    }

    /// Whether every cell is a corner (nothing left to split).
    fn is_cell(self) -> bool {
        self.r.1 - self.r.0 <= 1 && self.c.1 - self.c.0 <= 1
    }

    fn corners(self) -> [(usize, usize); 4] {
        [
            (self.r.0, self.c.0),
            (self.r.0, self.c.1),
            (self.r.1, self.c.0),
            (self.r.1, self.c.1),
        ]
    }
}

/// The lattice of one axis of `n` cells: every `spacing`-th index and the last.
fn ticks(n: usize, spacing: usize) -> Vec<usize> {
    let mut t: Vec<usize> = (0..n).step_by(spacing).collect();
    if t.last() != Some(&(n - 1)) {
        t.push(n - 1);
    }
    t
}

/// The map of `rows` × `cols` cells whose values `compute` gives (one batch of `(row, col)`
/// cells at a time, its values in the order asked), refined from a lattice of every `spacing`-th
/// cell (see the module docs). `spacing` 1 computes every cell. An empty grid is an empty map;
/// `spacing` 0 is taken as 1.
pub fn refine<V, E, F>(
    rows: usize,
    cols: usize,
    spacing: usize,
    mut compute: F,
) -> Result<Refined<V>, E>
where
    V: Clone + PartialEq,
    F: FnMut(&[(usize, usize)]) -> Result<Vec<V>, E>,
{
    let mut grid: Vec<Option<V>> = vec![None; rows * cols];
    if rows == 0 || cols == 0 {
        return Ok(Refined {
            values: Vec::new(),
            computed: Vec::new(),
        });
    }
    let s = spacing.max(1);
    let (tr, tc) = (ticks(rows, s), ticks(cols, s));
    let span = |t: &[usize]| -> Vec<(usize, usize)> {
        if t.len() == 1 {
            vec![(t[0], t[0])]
        } else {
            t.windows(2).map(|w| (w[0], w[1])).collect()
        }
    };
    let spans_c = span(&tc);
    let mut pending: Vec<Block> = span(&tr)
        .into_iter()
        .flat_map(|r| spans_c.iter().map(move |&c| Block { r, c }))
        .collect();
    let mut accepted: Vec<Block> = Vec::new();
    let mut wanted: Vec<(usize, usize)> = pending.iter().flat_map(|b| b.corners()).collect();
    loop {
        run(&mut grid, cols, &mut wanted, &mut compute)?;
        if pending.is_empty() {
            // a block accepted earlier may have had cells of its edges computed since
            let (open, kept): (Vec<Block>, Vec<Block>) =
                accepted.into_iter().partition(|&b| !agrees(&grid, cols, b));
            accepted = kept;
            if open.is_empty() {
                break;
            }
            pending = open;
        }
        let mut next = Vec::new();
        for b in pending.drain(..) {
            if agrees(&grid, cols, b) {
                accepted.push(b);
            } else if !b.is_cell() {
                for q in b.split() {
                    wanted.extend(q.corners());
                    next.push(q);
                }
            }
        }
        pending = next;
    }
    let computed: Vec<bool> = grid.iter().map(Option::is_some).collect();
    for b in accepted {
        let known = b
            .cells()
            .find_map(|(i, j)| grid[i * cols + j].clone())
            .expect("an accepted block has its corners computed");
        for (i, j) in b.cells() {
            grid[i * cols + j].get_or_insert_with(|| known.clone());
        }
    }
    Ok(Refined {
        values: grid
            .into_iter()
            .map(|v| v.expect("every cell lies in a computed or an accepted block"))
            .collect(),
        computed,
    })
}

/// Computes the `wanted` cells not yet computed (once each, in row-major order).
fn run<V, E, F>(
    grid: &mut [Option<V>],
    cols: usize,
    wanted: &mut Vec<(usize, usize)>,
    compute: &mut F,
) -> Result<(), E>
where
    F: FnMut(&[(usize, usize)]) -> Result<Vec<V>, E>,
{
    wanted.sort_unstable();
    wanted.dedup();
    wanted.retain(|&(i, j)| grid[i * cols + j].is_none());
    if !wanted.is_empty() {
        let values = compute(wanted)?;
        assert_eq!(values.len(), wanted.len(), "one value per cell asked");
        for (&(i, j), v) in wanted.iter().zip(values) {
            grid[i * cols + j] = Some(v);
        }
    }
    wanted.clear();
    Ok(())
}

/// Whether every computed cell of `b` has the same value.
fn agrees<V: PartialEq>(grid: &[Option<V>], cols: usize, b: Block) -> bool {
    let mut known = b.cells().filter_map(|(i, j)| grid[i * cols + j].as_ref());
    match known.next() {
        Some(first) => known.all(|v| v == first),
        None => true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The map of `f` refined from `spacing`, with the number of cells computed.
    fn map(
        rows: usize,
        cols: usize,
        spacing: usize,
        f: impl Fn(usize, usize) -> u8,
    ) -> (Vec<u8>, usize) {
        let mut calls = 0;
        let m = refine(rows, cols, spacing, |cells| {
            calls += cells.len();
            Ok::<_, ()>(cells.iter().map(|&(i, j)| f(i, j)).collect())
        })
        .unwrap();
        let computed = m.computed.iter().filter(|&&c| c).count();
        assert_eq!(calls, computed, "each cell computed once");
        (m.values, computed)
    }

    fn exact(rows: usize, cols: usize, f: impl Fn(usize, usize) -> u8) -> Vec<u8> {
        (0..rows * cols).map(|k| f(k / cols, k % cols)).collect()
    }

    /// Regions a verdict map has: half-planes, a disc, a band, three verdicts meeting, a
    /// staircase.
    fn shapes() -> Vec<Box<dyn Fn(usize, usize) -> u8>> {
        vec![
            Box::new(|i, j| u8::from(3 * i + j > 200)),
            Box::new(|i, j| {
                let (x, y) = (i as f64 - 40.0, j as f64 - 60.0);
                u8::from(x * x + y * y < 900.0)
            }),
            Box::new(|i, _| u8::from((30..45).contains(&i))),
            Box::new(|i, j| match (i < 50, j < 70) {
                (true, _) => 0,
                (false, true) => 1,
                (false, false) => 2,
            }),
            Box::new(|i, j| u8::from(j / 10 > i / 13)),
        ]
    }

    #[test]
    fn regions_wider_than_the_spacing_come_out_exact_with_fewer_cells() {
        let (rows, cols) = (97, 131);
        for (n, f) in shapes().iter().enumerate() {
            let want = exact(rows, cols, f);
            for spacing in [2, 4, 8, 16] {
                let (got, computed) = map(rows, cols, spacing, f);
                assert_eq!(got, want, "shape {n}, spacing {spacing}");
                assert!(
                    computed < rows * cols / 2,
                    "shape {n}, spacing {spacing}: {computed} of {} computed",
                    rows * cols
                );
            }
        }
    }

    #[test]
    fn spacing_one_computes_every_cell() {
        let f = |i: usize, j: usize| u8::from((i * 7 + j * 3).is_multiple_of(5));
        let (got, computed) = map(23, 17, 1, f);
        assert_eq!(got, exact(23, 17, f));
        assert_eq!(computed, 23 * 17);
        // 0 is taken as 1
        assert_eq!(map(23, 17, 0, f).1, 23 * 17);
    }

    #[test]
    fn a_uniform_map_computes_only_the_lattice() {
        let (got, computed) = map(300, 300, 8, |_, _| 4);
        assert!(got.iter().all(|&v| v == 4));
        // ticks 0, 8, …, 296 and 299 on each axis
        assert_eq!(computed, 39 * 39);
    }

    #[test]
    fn thin_grids_and_an_empty_one() {
        let f = |i: usize, j: usize| u8::from(i + j > 40);
        for (rows, cols) in [(1, 100), (100, 1), (1, 1), (2, 3), (9, 9)] {
            for spacing in [1, 3, 8, 200] {
                assert_eq!(map(rows, cols, spacing, f).0, exact(rows, cols, f));
            }
        }
        assert!(map(0, 10, 8, f).0.is_empty());
    }

    #[test]
    fn an_island_inside_one_block_is_missed_as_the_module_states() {
        // one odd cell strictly inside a block of the 8-lattice, touching no computed cell
        let f = |i: usize, j: usize| u8::from((i, j) == (13, 21));
        let (got, _) = map(40, 40, 8, f);
        assert!(got.iter().all(|&v| v == 0));
        // on the lattice it is found
        assert_eq!(map(40, 40, 1, f).0, exact(40, 40, f));
    }

    #[test]
    fn a_difference_found_on_a_neighbours_edge_reopens_an_accepted_block() {
        // lattice columns 0, 8, 16: the right block's corners at column 16 find the region, its
        // refinement finds (4, 8) on the shared edge, whose left block's corners all agree: that
        // block must be reopened to find (4, 5..=7)
        let f = |i: usize, j: usize| u8::from(j == 16 || (i == 4 && j >= 5));
        let want = exact(9, 17, f);
        assert_eq!(map(9, 17, 8, f).0, want);
    }

    #[test]
    fn the_first_error_is_returned() {
        let r = refine(10, 10, 4, |cells| {
            if cells.len() > 5 {
                Err("too many")
            } else {
                Ok(vec![0u8; cells.len()])
            }
        });
        assert_eq!(r, Err("too many"));
    }
}
