//! Sharded sweeps: one grid split into N interleaved parts that run anywhere (the tasks of a SLURM
//! job array, several machines) and merge back into exactly the rows of a single run.
//!
//! **The split.** Shard K of N (0 ≤ K < N) holds the grid points i with i mod N = K. Interleaving
//! rather than cutting the grid into N blocks balances the shards: the cost of a point varies
//! with the parameters (a small γ or a large ω takes more steps), and a block of the grid would
//! hand one shard all the expensive corner, while every N-th point is a sample of the whole grid.
//!
//! **The merge** streams: each shard file is in grid order, so grid point i is the next row of
//! shard i mod N, and the merged rows come out in grid order reading every file once, in memory
//! that does not grow with the grid. [`plan`] checks the files' settings (the same grid, options
//! and version; every shard present once) before a row is read; [`Plan::merge`] checks every row
//! (the right index, the grid's parameters, nothing missing, nothing left over) as it passes.

use super::{RowError, Settings, SweepRow};
use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

/// Shard `index` of `count`: the grid points i with i mod count = index. Written `K/N`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// K, from 0 (as `$SLURM_ARRAY_TASK_ID` of `--array=0-(N-1)`).
    pub index: usize,
    /// N ≥ 1.
    pub count: usize,
}

impl Shard {
    /// Parses `K/N` with 0 ≤ K < N; errors name the text.
    ///
    /// ```
    /// use hdgear::sweep::Shard;
    /// let s = Shard::parse("2/4").unwrap();
    /// assert_eq!(s.indices(11).collect::<Vec<_>>(), [2, 6, 10]);
    /// assert!(Shard::parse("4/4").is_err());
    /// ```
    pub fn parse(text: &str) -> Result<Shard> {
        let bad = |reason: &str| Error::InvalidInput {
            what: "shard",
            text: text.to_string(),
            reason: reason.to_string(),
        };
        let (k, n) = text
            .split_once('/')
            .ok_or_else(|| bad("expected K/N, e.g. 0/4 for the first of four shards"))?;
        let whole = |s: &str, what: &str| {
            s.trim()
                .parse::<usize>()
                .map_err(|_| bad(&format!("{what} '{s}' is not a whole number")))
        };
        let (index, count) = (whole(k, "K")?, whole(n, "N")?);
        if count == 0 {
            return Err(bad("N must be ≥ 1"));
        }
        if index >= count {
            return Err(bad(&format!(
                "K counts from 0: shard K of {count} needs 0 ≤ K ≤ {}",
                count - 1
            )));
        }
        Ok(Shard { index, count })
    }

    /// True when grid point `i` is in this shard.
    pub fn contains(&self, i: usize) -> bool {
        i % self.count == self.index
    }

    /// This shard's points of a grid of `len` points, in grid order.
    pub fn indices(&self, len: usize) -> impl Iterator<Item = usize> {
        (self.index..len).step_by(self.count)
    }

    /// Number of this shard's points in a grid of `len` points.
    pub fn len(&self, len: usize) -> usize {
        len.saturating_sub(self.index).div_ceil(self.count)
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// Why shards cannot be merged. Each names the file and says what to do.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MergeError {
    /// No files were given.
    #[error("no shard files given")]
    NoFiles,
    /// A file holds a whole sweep (or a partial one), not a shard.
    #[error("{file} is not a shard of a sweep (its settings name no shard)")]
    NotAShard {
        /// The file.
        file: String,
    },
    /// A file's grid is not a valid grid (the file was edited).
    #[error("{file}: its grid is invalid")]
    InvalidGrid {
        /// The file.
        file: String,
        /// What is wrong with the grid.
        #[source]
        error: Box<Error>,
    },
    /// Two files of different sweeps (grid, options, version or number of shards).
    #[error(
        "{file} is not a shard of the same sweep as {first}: {key} is {here} there and {there} in {first}"
    )]
    OtherSettings {
        /// The file that differs.
        file: String,
        /// The first file, which the others are compared with.
        first: String,
        /// The first setting that differs (a path into the settings, e.g. `grid.axes[0].end`).
        key: String,
        /// Its value in `source`.
        here: String,
        /// Its value in `first`.
        there: String,
    },
    /// Two files of the same shard.
    #[error("shard {shard} is given twice: {first} and {second}")]
    DuplicateShard {
        /// The shard.
        shard: Shard,
        /// One file.
        first: String,
        /// The other.
        second: String,
    },
    /// Shards not given.
    #[error(
        "{} of {count} missing: rerun the sweep for {}",
        if missing.len() == 1 { format!("shard {}", missing[0]) }
        else { format!("shards {}", list(missing)) },
        if missing.len() == 1 { "it" } else { "them" }
    )]
    MissingShards {
        /// The missing shard indices (K).
        missing: Vec<usize>,
        /// N.
        count: usize,
    },
    /// A row that does not belong where it is.
    #[error("{file}: {error}")]
    Row {
        /// The file.
        file: String,
        /// What is wrong with the row (in the message, so not also a source).
        error: RowError,
    },
    /// A shard file that ends before its last grid point (an unfinished shard).
    #[error(
        "{file} ends before grid point {index} of shard {shard}: resume that shard to finish it"
    )]
    Incomplete {
        /// The file.
        file: String,
        /// Its shard.
        shard: Shard,
        /// The first grid point it lacks.
        index: usize,
    },
    /// A row other than the one due next (rows missing or out of grid order).
    #[error(
        "{file}: expected the row of grid point {expected} next, found grid point {found} (rows missing or out of order; was the file edited?)"
    )]
    OutOfOrder {
        /// The file.
        file: String,
        /// The grid point due.
        expected: usize,
        /// The row's grid point.
        found: usize,
    },
    /// Rows after the shard's last grid point.
    #[error("{file} has rows after the last grid point of its shard (grid point {index})")]
    Extra {
        /// The file.
        file: String,
        /// The extra row's grid point.
        index: usize,
    },
}

/// Up to eight numbers, then "…".
fn list(v: &[usize]) -> String {
    let mut s: Vec<String> = v.iter().take(8).map(ToString::to_string).collect();
    if v.len() > 8 {
        s.push(format!("… ({} in all)", v.len()));
    }
    s.join(", ")
}

/// A checked set of shard files: the settings of the whole sweep and, for each shard K, which
/// file holds it.
#[derive(Debug)]
pub struct Plan {
    settings: Settings,
    count: usize,
    /// `file[k]`: the position (in the caller's list) of the file holding shard k.
    file: Vec<usize>,
    sources: Vec<String>,
}

/// Checks the settings of shard files (`(source, settings)` in any order): the same sweep, each
/// shard of it exactly once. No row is read.
///
/// ```
/// use hdgear::sweep::{Grid, Axis, Settings, Shard, plan};
/// let grid = Grid::new(Default::default(), vec![Axis::parse("gamma=1:2:5").unwrap()]).unwrap();
/// let whole = Settings::new(&grid, &Default::default());
/// let part = |k| ("s.csv".to_string(), whole.clone().with_shard(Some(Shard { index: k, count: 3 })));
/// let err = plan(vec![part(0), part(2)]).unwrap_err();
/// assert_eq!(err.to_string(), "shard 1 of 3 missing: rerun the sweep for it");
/// assert_eq!(plan(vec![part(2), part(0), part(1)]).unwrap().settings(), &whole);
/// ```
pub fn plan(files: Vec<(String, Settings)>) -> std::result::Result<Plan, MergeError> {
    let Some((first, s0)) = files.first() else {
        return Err(MergeError::NoFiles);
    };
    let count = s0
        .shard
        .ok_or_else(|| MergeError::NotAShard {
            file: first.clone(),
        })?
        .count;
    let mut file: Vec<Option<usize>> = vec![None; count];
    for (pos, (source, s)) in files.iter().enumerate() {
        let shard = s.shard.ok_or_else(|| MergeError::NotAShard {
            file: source.clone(),
        })?;
        // compare everything but the shard's index (its count must agree)
        let like_first = s.clone().with_shard(Some(Shard { index: 0, ..shard }));
        let first_like = s0.clone().with_shard(Some(Shard { index: 0, count }));
        if let Some(d) = like_first.first_difference(&first_like) {
            return Err(MergeError::OtherSettings {
                file: source.clone(),
                first: first.clone(),
                key: d.key,
                here: d.here,
                there: d.there,
            });
        }
        super::Grid::new(s.grid.base, s.grid.axes.clone()).map_err(|e| {
            MergeError::InvalidGrid {
                file: source.clone(),
                error: Box::new(e),
            }
        })?;
        if let Some(prev) = file[shard.index].replace(pos) {
            return Err(MergeError::DuplicateShard {
                shard,
                first: files[prev].0.clone(),
                second: source.clone(),
            });
        }
    }
    let missing: Vec<usize> = (0..count).filter(|&k| file[k].is_none()).collect();
    if !missing.is_empty() {
        return Err(MergeError::MissingShards { missing, count });
    }
    Ok(Plan {
        settings: s0.clone().with_shard(None),
        count,
        file: file.into_iter().flatten().collect(),
        sources: files.into_iter().map(|(s, _)| s).collect(),
    })
}

impl Plan {
    /// The settings of the whole sweep: the `meta` of its output.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// Reads the files' rows (`rows[j]` holds the rows of file j of the list given to [`plan`],
    /// in file order) and hands them to `emit` in grid order, checking each. Returns the number
    /// of rows. Errors of the readers and of `emit` pass through; a wrong row is a
    /// [`MergeError`] converted into `E`.
    pub fn merge<R, E>(
        &self,
        mut rows: Vec<R>,
        mut emit: impl FnMut(SweepRow) -> std::result::Result<(), E>,
    ) -> std::result::Result<usize, E>
    where
        R: Iterator<Item = std::result::Result<SweepRow, E>>,
        E: From<MergeError>,
    {
        let len = self.settings.grid.len();
        for i in 0..len {
            let k = i % self.count;
            let pos = self.file[k];
            let source = || self.sources[pos].clone();
            let Some(row) = rows[pos].next().transpose()? else {
                return Err(MergeError::Incomplete {
                    file: source(),
                    shard: Shard {
                        index: k,
                        count: self.count,
                    },
                    index: i,
                }
                .into());
            };
            if row.index != i {
                return Err(MergeError::OutOfOrder {
                    file: source(),
                    expected: i,
                    found: row.index,
                }
                .into());
            }
            self.settings
                .check_row(&row)
                .map_err(|error| MergeError::Row {
                    file: source(),
                    error,
                })?;
            emit(row)?;
        }
        for (pos, r) in rows.iter_mut().enumerate() {
            if let Some(row) = r.next().transpose()? {
                return Err(MergeError::Extra {
                    file: self.sources[pos].clone(),
                    index: row.index,
                }
                .into());
            }
        }
        Ok(len)
    }
}
