//! Writing the report's files: the manifest of what hdgear wrote (so that only those are
//! overwritten without `--force`), atomic writes, and the record to the manifest after each.

use super::MANIFEST;
use crate::error::{Error, Result};
use crate::output::plot::{self, Figure};
use crate::output::{Format, Record, RecordWriter, write_atomic};
use rayon::prelude::*;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The files hdgear's manifest in `dir` lists.
fn manifest(dir: &Path) -> Vec<String> {
    std::fs::read_to_string(dir.join(MANIFEST))
        .map(|t| t.lines().map(str::to_string).collect())
        .unwrap_or_default()
}

/// Rewrites the manifest: what it listed before and what this run has written so far (saved
/// after every stage, so an interrupted report can be rerun without `--force`).
fn save_manifest(dir: &Path, before: &[String], files: &[String]) -> Result<()> {
    let mut all: Vec<String> = before.iter().chain(files).cloned().collect();
    all.sort();
    all.dedup();
    write_atomic(&dir.join(MANIFEST), (all.join("\n") + "\n").as_bytes())
}

/// Files in `dir`, `dir/figures` and `dir/data` that hdgear's manifest does not list.
fn foreign_files(dir: &Path) -> Vec<String> {
    let listed = manifest(dir);
    let mut out = Vec::new();
    for sub in ["", "figures", "data"] {
        let Ok(entries) = std::fs::read_dir(dir.join(sub)) else {
            continue;
        };
        for e in entries.flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            let rel = if sub.is_empty() {
                name.clone()
            } else {
                format!("{sub}/{name}")
            };
            let is_dir = e.file_type().is_ok_and(|t| t.is_dir());
            if name == MANIFEST
                || (is_dir && sub.is_empty() && (name == "figures" || name == "data"))
            {
                continue;
            }
            if !listed.contains(&rel) {
                out.push(rel);
            }
        }
    }
    out.sort();
    out
}

/// Writes files into the report directory, listing each in the manifest just before it is
/// written (so an interrupted report can be rerun without `--force`).
pub(super) struct Files {
    dir: PathBuf,
    before: Vec<String>,
    /// Written so far, relative to the directory.
    pub written: Vec<String>,
}

impl Files {
    /// Checks `dir` (created if missing) holds nothing hdgear did not write, unless `force`.
    pub fn open(dir: &Path, force: bool) -> Result<Files> {
        if dir.exists() && !dir.is_dir() {
            return Err(Error::InvalidInput {
                what: "report directory",
                text: dir.display().to_string(),
                reason: "exists and is not a directory".into(),
            });
        }
        let foreign = foreign_files(dir);
        if !force && !foreign.is_empty() {
            return Err(Error::ForeignFiles {
                dir: dir.display().to_string(),
                files: foreign,
            });
        }
        std::fs::create_dir_all(dir.join("figures")).map_err(io(dir))?;
        std::fs::create_dir_all(dir.join("data")).map_err(io(dir))?;
        let files = Files {
            dir: dir.to_path_buf(),
            before: manifest(dir),
            written: Vec::new(),
        };
        // the manifest first, before any computing: a directory the report cannot write to (a
        // full disk, no permission) is refused at once, and a report stopped midway leaves a
        // directory that names itself hdgear's (a rerun takes it without --force)
        save_manifest(&files.dir, &files.before, &files.written)?;
        Ok(files)
    }

    /// Writes `bytes` to `name` (relative) atomically, claimed first.
    pub fn bytes(&mut self, name: &str, bytes: &[u8]) -> Result<()> {
        self.claim(name)?;
        self.write_claimed(name, bytes)
    }

    /// Writes `bytes` to `name` (relative), already claimed ([`Files::claim`]), atomically; from
    /// any thread.
    pub fn write_claimed(&self, name: &str, bytes: &[u8]) -> Result<()> {
        write_atomic(&self.dir.join(name), bytes)
    }

    /// Lists `name` in the manifest before it is written (by [`Files::bytes`] or by someone
    /// else: a PNG renderer). In this order a signal can never leave a file hdgear wrote
    /// unlisted (it did when the manifest was saved after the file: a rerun then refused the
    /// directory); a listed file that was never written is harmless.
    pub fn claim(&mut self, name: &str) -> Result<()> {
        self.written.push(name.to_string());
        save_manifest(&self.dir, &self.before, &self.written)
    }

    /// The path of `name` in the directory.
    pub fn path(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    /// `rows` as CSV.
    pub fn csv<T: Record>(&mut self, name: &str, rows: &[T]) -> Result<()> {
        let path = self.path(name);
        let mut w = RecordWriter::<_, T>::new(Vec::new(), Format::Csv, &serde_json::Value::Null)
            .map_err(io(&path))?;
        for r in rows {
            w.row(r).map_err(io(&path))?;
        }
        let bytes = w.finish().map_err(io(&path))?;
        self.bytes(name, &bytes)
    }

    /// Every figure of `figures` as `figures/NAME.svg` and `.png`; returns the SVG texts, in
    /// order. Every figure's two files are listed first (see [`Files::claim`]), then the
    /// figures are drawn and written on all cores: drawing is most of a report's writing time,
    /// and one figure's files do not depend on another's.
    pub fn figures(&mut self, figures: &[Figure]) -> Result<Vec<String>> {
        let names: Vec<(String, String)> = figures
            .iter()
            .map(|f| {
                (
                    format!("figures/{}.svg", f.name),
                    format!("figures/{}.png", f.name),
                )
            })
            .collect();
        for (svg, png) in &names {
            self.claim(svg)?;
            self.claim(png)?;
        }
        figures
            .par_iter()
            .zip(&names)
            .map(|(f, (svg_name, png_name))| {
                let svg = plot::svg(f)?;
                self.write_claimed(svg_name, svg.as_bytes())?;
                plot::png(f, &self.path(png_name))?;
                Ok(svg)
            })
            .collect()
    }

    /// `v` as pretty JSON.
    pub fn json<T: Serialize>(&mut self, name: &str, v: &T) -> Result<()> {
        let path = self.path(name);
        let text = serde_json::to_string_pretty(v).map_err(|e| io(&path)(e.into()))?;
        self.bytes(name, text.as_bytes())
    }
}

fn io(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |source| Error::Io {
        path: path.to_path_buf(),
        source,
    }
}
