//! Parquet output of the commands: each cell equals the CSV of the same run.

/// Parquet output (only in builds with the `parquet` feature, the default).
#[cfg(feature = "parquet")]
mod parquet_files {
    use crate::common::hdgear;
    use std::path::Path;

    /// Each cell of a Parquet file, as the text the CSV writer gives the same value (a null as an
    /// empty field; doubles compared by value, NaN = NaN), checked against the CSV of the same run.
    fn assert_parquet_equals_csv(parquet_path: &Path, csv_path: &Path) -> usize {
        use parquet::file::reader::{FileReader, SerializedFileReader};
        use parquet::record::Field;
        let reader = SerializedFileReader::new(std::fs::File::open(parquet_path).unwrap()).unwrap();
        let mut csv = csv::Reader::from_path(csv_path).unwrap();
        let header: Vec<String> = csv.headers().unwrap().iter().map(String::from).collect();
        let mut n = 0;
        for (row, rec) in reader.get_row_iter(None).unwrap().zip(csv.records()) {
            let (row, rec) = (row.unwrap(), rec.unwrap());
            for (j, ((name, field), text)) in row.get_column_iter().zip(rec.iter()).enumerate() {
                assert_eq!(name, &header[j]);
                let ok = match field {
                    Field::Null => text.is_empty(),
                    Field::Long(v) => v.to_string() == text,
                    Field::Double(v) => {
                        let t: f64 = text.parse().unwrap();
                        (v.is_nan() && t.is_nan()) || v.to_bits() == t.to_bits()
                    }
                    Field::Str(s) => s == text,
                    other => panic!("unexpected {other:?}"),
                };
                assert!(ok, "row {n}, {name}: parquet {field:?}, csv '{text}'");
            }
            n += 1;
        }
        assert_eq!(n as i64, reader.metadata().file_metadata().num_rows());
        n
    }

    #[test]
    fn parquet_holds_the_csv_values_in_several_row_groups() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        // 60,001 samples: a row group of 32,768 rows and one of 27,233
        for out in ["t.csv", "t.parquet"] {
            let o = hdgear()
                .current_dir(d)
                .args([
                    "simulate", "--t-end", "600", "--dt", "0.01", "--quiet", "--out", out,
                ])
                .output()
                .unwrap();
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        }
        assert_eq!(
            assert_parquet_equals_csv(&d.join("t.parquet"), &d.join("t.csv")),
            60_001
        );
        let meta = parquet::file::reader::FileReader::metadata(
            &parquet::file::reader::SerializedFileReader::new(
                std::fs::File::open(d.join("t.parquet")).unwrap(),
            )
            .unwrap(),
        )
        .clone();
        assert_eq!(meta.num_row_groups(), 2);
    }

    #[test]
    fn parquet_trajectories_carry_the_model_s_internal_states() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::write(d.join("m.toml"), "[lugre]\n[washout]\nkw = 2\n").unwrap();
        for out in ["m.csv", "m.parquet"] {
            let args = [
                "simulate", "--config", "m.toml", "--t-end", "50", "--quiet", "--out",
            ];
            let o = hdgear()
                .current_dir(d)
                .args(args)
                .arg(out)
                .output()
                .unwrap();
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        }
        assert_eq!(
            assert_parquet_equals_csv(&d.join("m.parquet"), &d.join("m.csv")),
            1001
        );
        let csv = std::fs::read_to_string(d.join("m.csv")).unwrap();
        assert!(csv.starts_with("t,a,x,xdot,s,xi\n"), "{}", &csv[..40]);
    }

    #[test]
    fn parquet_sweeps_keep_their_settings_and_merge_to_the_same_bytes() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        // a sweep with failed points (NaN, nulls, messages) and ∞: the settings travel along
        let grid = [
            "sweep",
            "--param",
            "gamma=0.001:0.1:3:log",
            "--param",
            "omega=1e-9:0.01:2:log",
            "--quiet",
        ];
        for out in ["s.csv", "s.parquet"] {
            assert!(
                hdgear()
                    .current_dir(d)
                    .args(grid)
                    .args(["--out", out])
                    .output()
                    .unwrap()
                    .status
                    .success()
            );
        }
        assert_eq!(
            assert_parquet_equals_csv(&d.join("s.parquet"), &d.join("s.csv")),
            6
        );
        let reader = parquet::file::reader::SerializedFileReader::new(
            std::fs::File::open(d.join("s.parquet")).unwrap(),
        )
        .unwrap();
        let kv = parquet::file::reader::FileReader::metadata(&reader)
            .file_metadata()
            .key_value_metadata()
            .unwrap()
            .iter()
            .find(|kv| kv.key == "hdgear.meta")
            .and_then(|kv| kv.value.clone())
            .unwrap();
        let settings: hdgear::sweep::Settings = serde_json::from_str(&kv).unwrap();
        assert_eq!(settings.grid.len(), 6);
        // merged shards give the same Parquet bytes as one run
        for k in 0..2 {
            let shard = format!("{k}/2");
            assert!(
                hdgear()
                    .current_dir(d)
                    .args(grid)
                    .args(["--out", "m.csv", "--shard", &shard])
                    .output()
                    .unwrap()
                    .status
                    .success()
            );
        }
        let o = hdgear()
            .current_dir(d)
            .args([
                "merge",
                "m.shard-0-of-2.csv",
                "m.shard-1-of-2.csv",
                "--out",
                "m.parquet",
            ])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert_eq!(
            std::fs::read(d.join("m.parquet")).unwrap(),
            std::fs::read(d.join("s.parquet")).unwrap()
        );
    }
}
