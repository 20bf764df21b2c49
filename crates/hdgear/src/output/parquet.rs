//! Records as Parquet: columnar, typed and compressed, for outputs of 10⁵–10⁶ rows that a CSV
//! makes slow to load (a 10⁶-row sweep; pandas reads it with `pd.read_parquet`).
//!
//! Each record is flattened into cells by a small serde serializer (nested structs become their
//! fields in order, as in the CSV columns; `None` is a null; enums their names). Rows are kept
//! for a row group of [`ROW_GROUP`] rows and then written column by column, so memory stays flat
//! however long the output. The column types come from the first row group: an integer column
//! is INT64, a number DOUBLE (NaN and ±∞ kept), text and enums UTF-8 strings, a column with only
//! nulls in the first group a string column; every column is OPTIONAL. The `meta` given to the
//! writer (the sweep's settings) is stored as JSON under the key-value metadata `hdgear.meta`.
//! No time stamp is written: the same rows give the same bytes. Compression: Snappy, with
//! dictionary encoding for the few-valued columns (mode, mechanism).

use parquet::basic::Compression;
use parquet::data_type::{BoolType, ByteArray, ByteArrayType, DoubleType, Int64Type};
use parquet::file::metadata::KeyValue;
use parquet::file::properties::WriterProperties;
use parquet::file::writer::SerializedFileWriter;
use serde::ser::{self, Impossible, Serialize};
use std::io::Write;
use std::sync::Arc;

/// Rows per row group.
pub const ROW_GROUP: usize = 32_768;

/// One value of a record.
#[derive(Clone, Debug, PartialEq)]
enum Cell {
    Null,
    Bool(bool),
    Int(i64),
    Float(f64),
    Text(String),
}

/// The physical type of a column.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Bool,
    Int,
    Float,
    Text,
}

impl Cell {
    fn kind(&self) -> Option<Kind> {
        match self {
            Cell::Null => None,
            Cell::Bool(_) => Some(Kind::Bool),
            Cell::Int(_) => Some(Kind::Int),
            Cell::Float(_) => Some(Kind::Float),
            Cell::Text(_) => Some(Kind::Text),
        }
    }
}

/// Streams records into a Parquet file.
pub struct ParquetWriter<W: Write + Send> {
    columns: Vec<&'static str>,
    meta: String,
    /// Row-major cells of the row group being filled.
    rows: Vec<Vec<Cell>>,
    kinds: Vec<Kind>,
    writer: Option<SerializedFileWriter<W>>,
    out: Option<W>,
}

fn io(e: impl std::fmt::Display) -> std::io::Error {
    std::io::Error::other(format!("parquet: {e}"))
}

impl<W: Write + Send> ParquetWriter<W> {
    /// A writer for records with `columns`, with `meta` (JSON) stored in the file's metadata.
    pub fn new(out: W, columns: Vec<&'static str>, meta: String) -> Self {
        ParquetWriter {
            columns,
            meta,
            rows: Vec::new(),
            kinds: Vec::new(),
            writer: None,
            out: Some(out),
        }
    }

    /// Appends one record.
    pub fn row(&mut self, record: &impl Serialize) -> std::io::Result<()> {
        let mut cells = Cells(Vec::with_capacity(self.columns.len()));
        record.serialize(&mut cells).map_err(io)?;
        if cells.0.len() != self.columns.len() {
            return Err(io(format!(
                "a record has {} values for {} columns",
                cells.0.len(),
                self.columns.len()
            )));
        }
        self.rows.push(cells.0);
        if self.rows.len() == ROW_GROUP {
            self.flush_group()?;
        }
        Ok(())
    }

    /// The column types, from the first row group.
    fn schema(&self) -> String {
        let fields: Vec<String> = self
            .columns
            .iter()
            .zip(&self.kinds)
            .map(|(name, kind)| match kind {
                Kind::Bool => format!("OPTIONAL BOOLEAN {name};"),
                Kind::Int => format!("OPTIONAL INT64 {name};"),
                Kind::Float => format!("OPTIONAL DOUBLE {name};"),
                Kind::Text => format!("OPTIONAL BYTE_ARRAY {name} (UTF8);"),
            })
            .collect();
        format!("message hdgear {{ {} }}", fields.join(" "))
    }

    fn start(&mut self) -> std::io::Result<()> {
        self.kinds = (0..self.columns.len())
            .map(|j| {
                self.rows
                    .iter()
                    .find_map(|r| r[j].kind())
                    .unwrap_or(Kind::Text)
            })
            .collect();
        let schema = parquet::schema::parser::parse_message_type(&self.schema()).map_err(io)?;
        let props = WriterProperties::builder()
            .set_compression(Compression::SNAPPY)
            .set_key_value_metadata(Some(vec![KeyValue::new(
                "hdgear.meta".to_string(),
                self.meta.clone(),
            )]))
            .build();
        let out = self.out.take().ok_or_else(|| io("writer already used"))?;
        self.writer =
            Some(SerializedFileWriter::new(out, Arc::new(schema), Arc::new(props)).map_err(io)?);
        Ok(())
    }

    fn flush_group(&mut self) -> std::io::Result<()> {
        if self.writer.is_none() {
            self.start()?;
        }
        let rows = std::mem::take(&mut self.rows);
        let Some(writer) = self.writer.as_mut() else {
            return Err(io("no writer"));
        };
        let mut group = writer.next_row_group().map_err(io)?;
        let mut j = 0;
        while let Some(mut col) = group.next_column().map_err(io)? {
            let name = self.columns[j];
            let def: Vec<i16> = rows.iter().map(|r| i16::from(r[j] != Cell::Null)).collect();
            let mismatch = |c: &Cell| {
                io(format!(
                    "column {name}: {c:?} in a {:?} column",
                    self.kinds[j]
                ))
            };
            match self.kinds[j] {
                Kind::Bool => {
                    let v = values(&rows, j, |c| match c {
                        Cell::Bool(b) => Ok(*b),
                        other => Err(mismatch(other)),
                    })?;
                    col.typed::<BoolType>().write_batch(&v, Some(&def), None)
                }
                Kind::Int => {
                    let v = values(&rows, j, |c| match c {
                        Cell::Int(i) => Ok(*i),
                        other => Err(mismatch(other)),
                    })?;
                    col.typed::<Int64Type>().write_batch(&v, Some(&def), None)
                }
                Kind::Float => {
                    let v = values(&rows, j, |c| match c {
                        Cell::Float(x) => Ok(*x),
                        Cell::Int(i) => Ok(*i as f64),
                        other => Err(mismatch(other)),
                    })?;
                    col.typed::<DoubleType>().write_batch(&v, Some(&def), None)
                }
                Kind::Text => {
                    let v = values(&rows, j, |c| {
                        Ok(ByteArray::from(match c {
                            Cell::Text(s) => s.as_str().into(),
                            Cell::Bool(b) => b.to_string().into_bytes(),
                            Cell::Int(i) => i.to_string().into_bytes(),
                            Cell::Float(x) => x.to_string().into_bytes(),
                            Cell::Null => Vec::new(),
                        }))
                    })?;
                    col.typed::<ByteArrayType>()
                        .write_batch(&v, Some(&def), None)
                }
            }
            .map_err(io)?;
            col.close().map_err(io)?;
            j += 1;
        }
        group.close().map_err(io)?;
        Ok(())
    }

    /// Writes the last row group and the footer; returns the inner writer.
    pub fn finish(mut self) -> std::io::Result<W> {
        if self.writer.is_none() {
            self.start()?;
        }
        if !self.rows.is_empty() {
            self.flush_group()?;
        }
        let writer = self.writer.take().ok_or_else(|| io("no writer"))?;
        let mut out = writer.into_inner().map_err(io)?;
        out.flush()?;
        Ok(out)
    }
}

/// The non-null values of column `j`.
fn values<T>(
    rows: &[Vec<Cell>],
    j: usize,
    f: impl Fn(&Cell) -> std::io::Result<T>,
) -> std::io::Result<Vec<T>> {
    rows.iter()
        .map(|r| &r[j])
        .filter(|c| **c != Cell::Null)
        .map(f)
        .collect()
}

/// A serializer that appends a record's scalar values, flattened, to a list of cells.
struct Cells(Vec<Cell>);

/// A value the flattening cannot hold (a sequence inside a record).
#[derive(Debug)]
struct Unsupported(String);

impl std::fmt::Display for Unsupported {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Unsupported {}

impl ser::Error for Unsupported {
    fn custom<T: std::fmt::Display>(msg: T) -> Self {
        Unsupported(msg.to_string())
    }
}

type Res = Result<(), Unsupported>;

fn unsupported<T>(what: &str) -> Result<T, Unsupported> {
    Err(Unsupported(format!("a {what} cannot be a Parquet cell")))
}

impl ser::Serializer for &mut Cells {
    type Ok = ();
    type Error = Unsupported;
    type SerializeSeq = Impossible<(), Unsupported>;
    type SerializeTuple = Impossible<(), Unsupported>;
    type SerializeTupleStruct = Impossible<(), Unsupported>;
    type SerializeTupleVariant = Impossible<(), Unsupported>;
    type SerializeMap = Self;
    type SerializeStruct = Self;
    type SerializeStructVariant = Impossible<(), Unsupported>;

    fn serialize_bool(self, v: bool) -> Res {
        self.0.push(Cell::Bool(v));
        Ok(())
    }
    fn serialize_i8(self, v: i8) -> Res {
        self.serialize_i64(v.into())
    }
    fn serialize_i16(self, v: i16) -> Res {
        self.serialize_i64(v.into())
    }
    fn serialize_i32(self, v: i32) -> Res {
        self.serialize_i64(v.into())
    }
    fn serialize_i64(self, v: i64) -> Res {
        self.0.push(Cell::Int(v));
        Ok(())
    }
    fn serialize_u8(self, v: u8) -> Res {
        self.serialize_i64(v.into())
    }
    fn serialize_u16(self, v: u16) -> Res {
        self.serialize_i64(v.into())
    }
    fn serialize_u32(self, v: u32) -> Res {
        self.serialize_i64(v.into())
    }
    fn serialize_u64(self, v: u64) -> Res {
        let v = i64::try_from(v).map_err(|_| Unsupported(format!("{v} exceeds INT64")))?;
        self.serialize_i64(v)
    }
    fn serialize_f32(self, v: f32) -> Res {
        self.serialize_f64(v.into())
    }
    fn serialize_f64(self, v: f64) -> Res {
        self.0.push(Cell::Float(v));
        Ok(())
    }
    fn serialize_char(self, v: char) -> Res {
        self.serialize_str(&v.to_string())
    }
    fn serialize_str(self, v: &str) -> Res {
        self.0.push(Cell::Text(v.to_string()));
        Ok(())
    }
    fn serialize_bytes(self, _: &[u8]) -> Res {
        unsupported("byte string")
    }
    fn serialize_none(self) -> Res {
        self.0.push(Cell::Null);
        Ok(())
    }
    fn serialize_some<T: ?Sized + Serialize>(self, v: &T) -> Res {
        v.serialize(self)
    }
    fn serialize_unit(self) -> Res {
        self.serialize_none()
    }
    fn serialize_unit_struct(self, _: &'static str) -> Res {
        self.serialize_none()
    }
    fn serialize_unit_variant(self, _: &'static str, _: u32, variant: &'static str) -> Res {
        self.serialize_str(variant)
    }
    fn serialize_newtype_struct<T: ?Sized + Serialize>(self, _: &'static str, v: &T) -> Res {
        v.serialize(self)
    }
    fn serialize_newtype_variant<T: ?Sized + Serialize>(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        v: &T,
    ) -> Res {
        v.serialize(self)
    }
    fn serialize_seq(self, _: Option<usize>) -> Result<Self::SerializeSeq, Unsupported> {
        unsupported("sequence")
    }
    fn serialize_tuple(self, _: usize) -> Result<Self::SerializeTuple, Unsupported> {
        unsupported("tuple")
    }
    fn serialize_tuple_struct(
        self,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeTupleStruct, Unsupported> {
        unsupported("tuple struct")
    }
    fn serialize_tuple_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeTupleVariant, Unsupported> {
        unsupported("tuple variant")
    }
    fn serialize_map(self, _: Option<usize>) -> Result<Self, Unsupported> {
        Ok(self)
    }
    fn serialize_struct(self, _: &'static str, _: usize) -> Result<Self, Unsupported> {
        Ok(self)
    }
    fn serialize_struct_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeStructVariant, Unsupported> {
        unsupported("struct variant")
    }
}

impl ser::SerializeStruct for &mut Cells {
    type Ok = ();
    type Error = Unsupported;
    fn serialize_field<T: ?Sized + Serialize>(&mut self, _: &'static str, v: &T) -> Res {
        v.serialize(&mut **self)
    }
    fn end(self) -> Res {
        Ok(())
    }
}

/// A flattened struct (`#[serde(flatten)]`) arrives as a map: its values are the cells.
impl ser::SerializeMap for &mut Cells {
    type Ok = ();
    type Error = Unsupported;
    fn serialize_key<T: ?Sized + Serialize>(&mut self, _: &T) -> Res {
        Ok(())
    }
    fn serialize_value<T: ?Sized + Serialize>(&mut self, v: &T) -> Res {
        v.serialize(&mut **self)
    }
    fn end(self) -> Res {
        Ok(())
    }
}
