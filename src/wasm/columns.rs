//! The per-point arrays of an analysis as the page's packed columns (www/columns.js; issue 31
//! item 3): the points of a 200,000-point scan cross to the page as typed arrays, not as a JSON
//! text of 200,000 objects (30 MB at 20,000 points) that the worker would parse and repack.
//!
//! A list is read through its items' own `Serialize` (every field of every point, in the order
//! serde writes them), one column per field, into the layout of www/columns.js:
//! `{$col, n, ...}` with `$col` one of
//! - `num` (`v`: Float64Array) or `numnull` (`v` with NaN at a null, `nul`: Uint8Array, 1 there);
//! - `const` (`v`: every value the same: null, a boolean or a string), `bool` (`v`: Uint8Array 0/1);
//! - `label` (`codes`: Int32Array into `labels`) or `text` (`s`: the strings end to end, `ends`:
//!   Int32Array, where each ends in UTF-16 code units);
//! - `vec` (lists of `k` numbers; `v`: Float64Array of n·k, point after point);
//! - `table` (objects; `keys` in order and `cols`: a packed column per key).
//!
//! A list whose items hold anything else (a list of strings, a value that is sometimes null and
//! sometimes text, a field some items leave out) is refused with [`NotColumns`]; the export then
//! leaves it in the JSON, where the worker packs it (www/columns.js `packAnalysis`).

use std::fmt;

use js_sys::{Array, Float64Array, Int32Array, Object, Reflect, Uint8Array};
use serde::ser::{self, Impossible, Serialize};
use wasm_bindgen::JsValue;

/// Why a list was not written as columns (it then travels as JSON).
#[derive(Debug)]
pub struct NotColumns(String);

impl fmt::Display for NotColumns {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "not written as columns: {}", self.0)
    }
}

impl std::error::Error for NotColumns {}

impl ser::Error for NotColumns {
    fn custom<T: fmt::Display>(msg: T) -> Self {
        NotColumns(msg.to_string())
    }
}

/// One field of every item, as read so far.
enum Col {
    /// Only nulls so far (their number; 0: no value yet).
    Nulls(usize),
    /// Numbers, NaN at a null and `nul` 1 there: `nul` empty until the first null, then as
    /// long as `v` up to the last null (0 at a number; the rows after it numbers).
    Num {
        v: Vec<f64>,
        nul: Vec<u8>,
    },
    Bool(Vec<u8>),
    Str(Vec<String>),
    /// Lists of `k` numbers, item after item.
    List {
        k: usize,
        v: Vec<f64>,
    },
    /// Objects: their keys in order, one column per key.
    Table {
        keys: Vec<&'static str>,
        cols: Vec<Col>,
    },
}

/// `items` as one packed column (`{$col, n, ...}` of www/columns.js).
pub fn packed<T: Serialize>(items: &[T]) -> Result<JsValue, NotColumns> {
    if items.is_empty() {
        return Err(NotColumns("an empty list".into()));
    }
    let mut col = Col::Nulls(0);
    for (row, item) in items.iter().enumerate() {
        item.serialize(Cell { col: &mut col, row })?;
    }
    Ok(col.into_js(items.len()))
}

/// Numbers as a packed `num` column (NaN stays NaN: the page reads it as the JSON's null).
pub(crate) fn packed_numbers(v: &[f64]) -> JsValue {
    Col::Num {
        v: v.to_vec(),
        nul: Vec::new(),
    }
    .into_js(v.len())
}

fn mixed(what: &str) -> NotColumns {
    NotColumns(format!("{what} in a field that held another kind of value"))
}

/// Sets `key` of the fresh object `o` (cannot fail on a plain object).
fn set(o: &Object, key: &str, v: &JsValue) {
    let _ = Reflect::set(o, &JsValue::from_str(key), v);
}

impl Col {
    fn into_js(self, n: usize) -> JsValue {
        let o = Object::new();
        set(&o, "n", &JsValue::from(n as u32));
        let kind = match self {
            Col::Nulls(_) => {
                set(&o, "v", &JsValue::NULL);
                "const"
            }
            Col::Num { v, mut nul } => {
                set(&o, "v", &Float64Array::from(&v[..]).into());
                if nul.is_empty() {
                    "num"
                } else {
                    nul.resize(v.len(), 0);
                    set(&o, "nul", &Uint8Array::from(&nul[..]).into());
                    "numnull"
                }
            }
            Col::Bool(v) => {
                if v.iter().all(|&x| x == v[0]) {
                    set(&o, "v", &JsValue::from_bool(v[0] == 1));
                    "const"
                } else {
                    set(&o, "v", &Uint8Array::from(&v[..]).into());
                    "bool"
                }
            }
            Col::Str(v) => strings(&o, v),
            Col::List { k, v } => {
                set(&o, "k", &JsValue::from(k as u32));
                set(&o, "v", &Float64Array::from(&v[..]).into());
                "vec"
            }
            Col::Table { keys, cols } => {
                let names = Array::new();
                let packed = Object::new();
                for (key, col) in keys.iter().zip(cols) {
                    names.push(&JsValue::from_str(key));
                    set(&packed, key, &col.into_js(n));
                }
                set(&o, "keys", &names.into());
                set(&o, "cols", &packed.into());
                "table"
            }
        };
        set(&o, "$col", &JsValue::from_str(kind));
        o.into()
    }
}

/// Strings: one value → `const`; few distinct (no more than 64 among the first 256, at most a
/// quarter of them) → `label`; else `text` (the rules of www/columns.js `packStrings`).
fn strings(o: &Object, v: Vec<String>) -> &'static str {
    let n = v.len();
    let first: std::collections::HashSet<&str> = v.iter().take(256).map(String::as_str).collect();
    let mut labels: Vec<&str> = Vec::new();
    let mut index: std::collections::HashMap<&str, i32> = std::collections::HashMap::new();
    let few = first.len() <= 64
        && v.iter().all(|s| {
            if !index.contains_key(s.as_str()) {
                index.insert(s.as_str(), labels.len() as i32);
                labels.push(s.as_str());
            }
            labels.len() <= n / 4 + 1
        });
    if few && labels.len() == 1 {
        set(o, "v", &JsValue::from_str(&v[0]));
        return "const";
    }
    if few {
        let codes: Vec<i32> = v.iter().map(|s| index[s.as_str()]).collect();
        set(o, "codes", &Int32Array::from(&codes[..]).into());
        let names = Array::new();
        for l in &labels {
            names.push(&JsValue::from_str(l));
        }
        set(o, "labels", &names.into());
        return "label";
    }
    let mut ends = Vec::with_capacity(n);
    let mut at = 0i32;
    for s in &v {
        at += s.encode_utf16().count() as i32;
        ends.push(at);
    }
    set(o, "s", &JsValue::from_str(&v.concat()));
    set(o, "ends", &Int32Array::from(&ends[..]).into());
    "text"
}

/// The serializer of one item's value into its column (`row`: the item's index).
struct Cell<'a> {
    col: &'a mut Col,
    row: usize,
}

impl Cell<'_> {
    fn number(self, x: f64) -> Result<(), NotColumns> {
        match self.col {
            Col::Nulls(k) => {
                let k = *k;
                let mut v = vec![f64::NAN; k];
                v.push(x);
                *self.col = Col::Num { v, nul: vec![1; k] };
            }
            // (`nul` not written at a number: 0 up to `v`'s length, [`Col::Num`])
            Col::Num { v, .. } => v.push(x),
            _ => return Err(mixed("a number")),
        }
        Ok(())
    }

    fn null(self) -> Result<(), NotColumns> {
        match self.col {
            Col::Nulls(k) => *k += 1,
            Col::Num { v, nul } => {
                nul.resize(v.len(), 0);
                v.push(f64::NAN);
                nul.push(1);
            }
            _ => return Err(mixed("a null")),
        }
        Ok(())
    }

    fn boolean(self, b: bool) -> Result<(), NotColumns> {
        match self.col {
            Col::Nulls(0) => *self.col = Col::Bool(vec![u8::from(b)]),
            Col::Bool(v) => v.push(u8::from(b)),
            _ => return Err(mixed("a boolean")),
        }
        Ok(())
    }

    fn string(self, s: &str) -> Result<(), NotColumns> {
        match self.col {
            Col::Nulls(0) => *self.col = Col::Str(vec![s.to_string()]),
            Col::Str(v) => v.push(s.to_string()),
            _ => return Err(mixed("a string")),
        }
        Ok(())
    }
}

fn refused<T>(what: &str) -> Result<T, NotColumns> {
    Err(NotColumns(format!("{what} in an item")))
}

/// The serializer's methods for numbers: each the number as f64 (integers of up to 2^53 exactly,
/// as in the JSON the page parsed before).
/// (One list of serde's number methods for [`Cell`] and [`Number`]: each calls its serializer's
/// own `number`.)
macro_rules! numbers {
    () => {
        numbers! {
            serialize_i8: i8,
            serialize_i16: i16,
            serialize_i32: i32,
            serialize_i64: i64,
            serialize_u8: u8,
            serialize_u16: u16,
            serialize_u32: u32,
            serialize_u64: u64,
            serialize_f32: f32,
            serialize_f64: f64
        }
    };
    ($($name:ident: $t:ty),*) => {
        $(fn $name(self, v: $t) -> Result<Self::Ok, NotColumns> {
            self.number(v as f64)
        })*
    };
}

impl<'a> ser::Serializer for Cell<'a> {
    type Ok = ();
    type Error = NotColumns;
    type SerializeSeq = ListCell<'a>;
    type SerializeTuple = ListCell<'a>;
    type SerializeTupleStruct = Impossible<(), NotColumns>;
    type SerializeTupleVariant = Impossible<(), NotColumns>;
    type SerializeMap = Impossible<(), NotColumns>;
    type SerializeStruct = TableCell<'a>;
    type SerializeStructVariant = Impossible<(), NotColumns>;

    fn serialize_bool(self, v: bool) -> Result<(), NotColumns> {
        self.boolean(v)
    }
    numbers!();
    fn serialize_char(self, v: char) -> Result<(), NotColumns> {
        self.string(&v.to_string())
    }
    fn serialize_str(self, v: &str) -> Result<(), NotColumns> {
        self.string(v)
    }
    fn serialize_bytes(self, _: &[u8]) -> Result<(), NotColumns> {
        refused("bytes")
    }
    fn serialize_none(self) -> Result<(), NotColumns> {
        self.null()
    }
    fn serialize_some<T: ?Sized + Serialize>(self, value: &T) -> Result<(), NotColumns> {
        value.serialize(self)
    }
    fn serialize_unit(self) -> Result<(), NotColumns> {
        self.null()
    }
    fn serialize_unit_struct(self, _: &'static str) -> Result<(), NotColumns> {
        self.null()
    }
    fn serialize_unit_variant(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
    ) -> Result<(), NotColumns> {
        self.string(variant)
    }
    fn serialize_newtype_struct<T: ?Sized + Serialize>(
        self,
        _: &'static str,
        value: &T,
    ) -> Result<(), NotColumns> {
        value.serialize(self)
    }
    fn serialize_newtype_variant<T: ?Sized + Serialize>(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: &T,
    ) -> Result<(), NotColumns> {
        refused("an enum with a value")
    }
    fn serialize_seq(self, _: Option<usize>) -> Result<ListCell<'a>, NotColumns> {
        if let Col::Nulls(0) = self.col {
            *self.col = Col::List {
                k: LIST_FIRST,
                v: Vec::new(),
            };
        }
        match self.col {
            Col::List { k, v } => Ok(ListCell {
                start: v.len(),
                k,
                v,
            }),
            _ => Err(mixed("a list")),
        }
    }
    fn serialize_tuple(self, len: usize) -> Result<ListCell<'a>, NotColumns> {
        self.serialize_seq(Some(len))
    }
    fn serialize_tuple_struct(
        self,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeTupleStruct, NotColumns> {
        refused("a tuple struct")
    }
    fn serialize_tuple_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeTupleVariant, NotColumns> {
        refused("an enum with values")
    }
    fn serialize_map(self, _: Option<usize>) -> Result<Self::SerializeMap, NotColumns> {
        refused("a map")
    }
    fn serialize_struct(self, _: &'static str, _: usize) -> Result<TableCell<'a>, NotColumns> {
        if let Col::Nulls(0) = self.col {
            *self.col = Col::Table {
                keys: Vec::new(),
                cols: Vec::new(),
            };
        }
        match self.col {
            Col::Table { .. } => Ok(TableCell {
                col: self.col,
                row: self.row,
                j: 0,
            }),
            _ => Err(mixed("an object")),
        }
    }
    fn serialize_struct_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeStructVariant, NotColumns> {
        refused("an enum with fields")
    }
}

/// [`Col::List`]'s `k` before its first item's list is read.
const LIST_FIRST: usize = usize::MAX;

/// A list of numbers in one item (a point's foot, its normal): its numbers written into its
/// [`Col::List`]'s `v` from `start` on, its length checked against the column's `k` (no
/// allocation an item: three a list had been ~20 ms of the page's 150 ms of packing a
/// 20,000-point scan's analysis, issue 31).
struct ListCell<'a> {
    k: &'a mut usize,
    v: &'a mut Vec<f64>,
    start: usize,
}

impl ListCell<'_> {
    fn element<T: ?Sized + Serialize>(&mut self, value: &T) -> Result<(), NotColumns> {
        self.v.push(value.serialize(Number)?);
        Ok(())
    }

    fn finish(self) -> Result<(), NotColumns> {
        let (k, k0) = (self.v.len() - self.start, self.k);
        if *k0 == LIST_FIRST {
            *k0 = k;
        } else if *k0 != k {
            return Err(NotColumns(format!(
                "lists of {k} and of {k0} numbers in one field"
            )));
        }
        Ok(())
    }
}

/// The serializer of an element of a list: its number (an option's, a newtype's), anything else
/// refused.
struct Number;

impl Number {
    /// A number of the list: the number as f64 (as [`Cell`]'s).
    fn number(self, x: f64) -> Result<f64, NotColumns> {
        Ok(x)
    }
}

/// [`Number`]'s methods for what is not a number.
macro_rules! not_numbers {
    ($($name:ident($($arg:ty),*) -> $ok:ty),*) => {
        $(fn $name(self, $(_: $arg),*) -> Result<$ok, NotColumns> {
            refused("a list holding other than numbers")
        })*
    };
}

impl ser::Serializer for Number {
    type Ok = f64;
    type Error = NotColumns;
    type SerializeSeq = Impossible<f64, NotColumns>;
    type SerializeTuple = Impossible<f64, NotColumns>;
    type SerializeTupleStruct = Impossible<f64, NotColumns>;
    type SerializeTupleVariant = Impossible<f64, NotColumns>;
    type SerializeMap = Impossible<f64, NotColumns>;
    type SerializeStruct = Impossible<f64, NotColumns>;
    type SerializeStructVariant = Impossible<f64, NotColumns>;

    numbers!();
    fn serialize_some<T: ?Sized + Serialize>(self, value: &T) -> Result<f64, NotColumns> {
        value.serialize(self)
    }
    fn serialize_newtype_struct<T: ?Sized + Serialize>(
        self,
        _: &'static str,
        value: &T,
    ) -> Result<f64, NotColumns> {
        value.serialize(self)
    }
    not_numbers! {
        serialize_bool(bool) -> f64,
        serialize_char(char) -> f64,
        serialize_str(&str) -> f64,
        serialize_bytes(&[u8]) -> f64,
        serialize_none() -> f64,
        serialize_unit() -> f64,
        serialize_unit_struct(&'static str) -> f64,
        serialize_unit_variant(&'static str, u32, &'static str) -> f64,
        serialize_seq(Option<usize>) -> Self::SerializeSeq,
        serialize_tuple(usize) -> Self::SerializeTuple,
        serialize_tuple_struct(&'static str, usize) -> Self::SerializeTupleStruct,
        serialize_tuple_variant(&'static str, u32, &'static str, usize) -> Self::SerializeTupleVariant,
        serialize_map(Option<usize>) -> Self::SerializeMap,
        serialize_struct(&'static str, usize) -> Self::SerializeStruct,
        serialize_struct_variant(&'static str, u32, &'static str, usize) -> Self::SerializeStructVariant
    }
    fn serialize_newtype_variant<T: ?Sized + Serialize>(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: &T,
    ) -> Result<f64, NotColumns> {
        refused("a list holding other than numbers")
    }
}

/// A list is a sequence or a tuple (serde's two traits, the same for a list of numbers).
macro_rules! list_of {
    ($($trait:path),*) => {
        $(impl $trait for ListCell<'_> {
            type Ok = ();
            type Error = NotColumns;
            fn serialize_element<T: ?Sized + Serialize>(&mut self, value: &T) -> Result<(), NotColumns> {
                self.element(value)
            }
            fn end(self) -> Result<(), NotColumns> {
                self.finish()
            }
        })*
    };
}

list_of!(ser::SerializeSeq, ser::SerializeTuple);

/// The fields of one item's object, field `j` next.
struct TableCell<'a> {
    col: &'a mut Col,
    row: usize,
    j: usize,
}

/// Whether two field names are the same: one item's field is the first's own `&'static str`
/// (the same address, no comparison of the text) unless the items' types differ.
fn same_key(a: &'static str, b: &'static str) -> bool {
    std::ptr::eq(a, b) || a == b
}

impl ser::SerializeStruct for TableCell<'_> {
    type Ok = ();
    type Error = NotColumns;

    fn serialize_field<T: ?Sized + Serialize>(
        &mut self,
        key: &'static str,
        value: &T,
    ) -> Result<(), NotColumns> {
        let Col::Table { keys, cols } = &mut *self.col else {
            return Err(mixed("an object"));
        };
        if self.j == keys.len() {
            if self.row > 0 {
                return Err(NotColumns(format!(
                    "item {} has the field \"{key}\" the first did not",
                    self.row
                )));
            }
            keys.push(key);
            cols.push(Col::Nulls(0));
        } else if !same_key(keys[self.j], key) {
            return Err(NotColumns(format!(
                "item {} has \"{key}\" where the first had \"{}\"",
                self.row, keys[self.j]
            )));
        }
        value.serialize(Cell {
            col: &mut cols[self.j],
            row: self.row,
        })?;
        self.j += 1;
        Ok(())
    }

    fn skip_field(&mut self, key: &'static str) -> Result<(), NotColumns> {
        Err(NotColumns(format!(
            "item {} leaves out the field \"{key}\"",
            self.row
        )))
    }

    fn end(self) -> Result<(), NotColumns> {
        match &*self.col {
            Col::Table { keys, .. } if keys.len() == self.j => Ok(()),
            _ => Err(NotColumns(format!(
                "item {} has fewer fields than the first",
                self.row
            ))),
        }
    }
}
