//! Stanford PLY reader and writer: `ascii`, `binary_little_endian` and
//! `binary_big_endian` 1.0, all eight scalar types under both their names (`char` /
//! `int8`, ..., `double` / `float64`).
//!
//! Read: the `vertex` element's `x`, `y`, `z` (any scalar type) and the `face`
//! element's `vertex_indices` (or `vertex_index`) list; every other element and
//! property is read past and ignored, so files with normals, colours, `edge` or
//! `material` elements load. Elements may come in any order; `vertex` and `face` may
//! each appear once, and data after the last element (or after the last record of an
//! ASCII file) is an error, as the header's counts then do not describe the file. An
//! element without properties is skipped in constant time (its records are empty); in
//! ASCII its count may not exceed the lines the rest of the file can hold.
//!
//! Written here rather than with `ply-rs` (last release 2018, no typed errors for
//! truncated binary data): the format is small, and owning the reader gives messages
//! that name the element and record where a file is cut or malformed.

use super::{parse_error, quote, RawMesh};
use crate::error::Result;
use crate::mesh::TriMesh;
use std::io::Write;
use std::path::Path;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Encoding {
    Ascii,
    LittleEndian,
    BigEndian,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }
    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
    fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }
    /// Smallest and largest value of an integer type (ASCII values are checked against it).
    fn range(self) -> (f64, f64) {
        match self {
            Scalar::I8 => (i8::MIN as f64, i8::MAX as f64),
            Scalar::U8 => (0.0, u8::MAX as f64),
            Scalar::I16 => (i16::MIN as f64, i16::MAX as f64),
            Scalar::U16 => (0.0, u16::MAX as f64),
            Scalar::I32 => (i32::MIN as f64, i32::MAX as f64),
            Scalar::U32 => (0.0, u32::MAX as f64),
            Scalar::F32 | Scalar::F64 => (f64::NEG_INFINITY, f64::INFINITY),
        }
    }
}

#[derive(Debug, Clone)]
enum Property {
    Scalar { ty: Scalar, name: String },
    List { count: Scalar, item: Scalar, name: String },
}

#[derive(Debug, Clone)]
struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

impl Element {
    /// Fewest bytes a record can take: the scalar sizes and list counts (binary), or one
    /// character and one separator per value (ASCII); the list at `index_slot` holds at
    /// least 3 items (a face with fewer is an error).
    fn min_record_bytes(&self, encoding: Encoding, index_slot: usize) -> usize {
        self.properties
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let items = if k == index_slot { 3 } else { 0 };
                match (encoding, p) {
                    (Encoding::Ascii, Property::Scalar { .. }) => 2,
                    (Encoding::Ascii, Property::List { .. }) => 2 * (1 + items),
                    (_, Property::Scalar { ty, .. }) => ty.size(),
                    (_, Property::List { count, item, .. }) => count.size() + items * item.size(),
                }
            })
            .sum()
    }
}

struct Header {
    encoding: Encoding,
    elements: Vec<Element>,
    /// Byte offset of the first data byte.
    body: usize,
}

/// Most elements plus properties a header may declare (real files have a handful): the
/// header is held as structs, several times the size of its text.
const MAX_HEADER_ITEMS: usize = 1 << 16;

fn parse_header(bytes: &[u8], path: &Path) -> Result<Header> {
    let bad = |line: usize, m: String| parse_error(path, format!("line {line}: bad header: {m}"));
    let mut pos = 0;
    let mut line_no = 0;
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut items = 0usize;
    // Line of the `vertex` and `face` elements: each may appear once.
    let mut seen: [Option<usize>; 2] = [None; 2];
    loop {
        let Some(len) = bytes[pos..].iter().position(|&b| b == b'\n') else {
            return Err(if line_no == 0 {
                parse_error(path, "bad header: first line must be 'ply'")
            } else {
                parse_error(path, "bad header: the file ends before 'end_header'")
            });
        };
        let line = String::from_utf8_lossy(&bytes[pos..pos + len]);
        let line = line.trim();
        pos += len + 1;
        line_no += 1;
        if line_no == 1 {
            if line != "ply" {
                return Err(bad(1, format!("first line must be 'ply', found {}", quote(line))));
            }
            continue;
        }
        let t: Vec<&str> = line.split_whitespace().collect();
        if matches!(t.first().copied(), Some("element" | "property")) {
            items += 1;
            if items > MAX_HEADER_ITEMS {
                return Err(bad(
                    line_no,
                    format!("more than {MAX_HEADER_ITEMS} elements and properties"),
                ));
            }
        }
        match t.first().copied() {
            None | Some("comment") | Some("obj_info") => {}
            Some("format") => {
                encoding = Some(match (t.get(1).copied(), t.get(2).copied()) {
                    (Some("ascii"), Some("1.0")) => Encoding::Ascii,
                    (Some("binary_little_endian"), Some("1.0")) => Encoding::LittleEndian,
                    (Some("binary_big_endian"), Some("1.0")) => Encoding::BigEndian,
                    _ => return Err(bad(line_no, format!("unsupported format line {}", quote(line)))),
                });
            }
            Some("element") => {
                let (Some(name), Some(count)) = (t.get(1), t.get(2).and_then(|c| c.parse::<usize>().ok())) else {
                    return Err(bad(
                        line_no,
                        format!("expected 'element <name> <count>', found {}", quote(line)),
                    ));
                };
                if let Some(k) = ["vertex", "face"].iter().position(|n| n == name) {
                    if let Some(first) = seen[k] {
                        return Err(bad(
                            line_no,
                            format!("a second '{name}' element (the first is on line {first}); a file holds one mesh"),
                        ));
                    }
                    seen[k] = Some(line_no);
                }
                elements.push(Element {
                    name: name.to_string(),
                    count,
                    properties: Vec::new(),
                });
            }
            Some("property") => {
                let Some(element) = elements.last_mut() else {
                    return Err(bad(line_no, "property before any element".into()));
                };
                let ty = |i: usize| {
                    t.get(i)
                        .and_then(|s| Scalar::parse(s))
                        .ok_or_else(|| bad(line_no, format!("unknown property type in {}", quote(line))))
                };
                let property = if t.get(1) == Some(&"list") {
                    let (count, item) = (ty(2)?, ty(3)?);
                    let name = t
                        .get(4)
                        .ok_or_else(|| bad(line_no, format!("list property without a name: {}", quote(line))))?;
                    if !count.is_integer() {
                        return Err(bad(
                            line_no,
                            format!("list count type must be an integer type: {}", quote(line)),
                        ));
                    }
                    Property::List {
                        count,
                        item,
                        name: name.to_string(),
                    }
                } else {
                    let ty = ty(1)?;
                    let name = t
                        .get(2)
                        .ok_or_else(|| bad(line_no, format!("property without a name: {}", quote(line))))?;
                    Property::Scalar {
                        ty,
                        name: name.to_string(),
                    }
                };
                element.properties.push(property);
            }
            Some("end_header") => break,
            Some(other) => return Err(bad(line_no, format!("unknown keyword {}", quote(other)))),
        }
    }
    let encoding = encoding.ok_or_else(|| parse_error(path, "bad header: no 'format' line"))?;
    Ok(Header {
        encoding,
        elements,
        body: pos,
    })
}

/// The data section, read one scalar at a time as `f64` (exact for every PLY type).
struct Body<'a> {
    data: &'a [u8],
    pos: usize,
    encoding: Encoding,
}

enum ReadFail {
    End,
    Bad(String),
}

impl<'a> Body<'a> {
    fn remaining(&self) -> usize {
        self.data.len() - self.pos
    }

    /// The next whitespace-separated token (ASCII), `None` at the end of the data.
    fn token(&mut self) -> Option<&'a [u8]> {
        let data: &'a [u8] = self.data;
        let rest = &data[self.pos..];
        let start = rest.iter().position(|b| !b.is_ascii_whitespace())?;
        let len = rest[start..]
            .iter()
            .position(|b| b.is_ascii_whitespace())
            .unwrap_or(rest.len() - start);
        self.pos += start + len;
        Some(&data[self.pos - len..self.pos])
    }

    fn scalar(&mut self, ty: Scalar) -> std::result::Result<f64, ReadFail> {
        let big_endian = match self.encoding {
            Encoding::Ascii => {
                let tok = self.token().ok_or(ReadFail::End)?;
                let tok = String::from_utf8_lossy(tok);
                let x: f64 = tok
                    .parse()
                    .map_err(|_| ReadFail::Bad(format!("{} is not a number", quote(&tok))))?;
                if ty.is_integer() {
                    let (lo, hi) = ty.range();
                    if !(x.fract() == 0.0 && lo <= x && x <= hi) {
                        return Err(ReadFail::Bad(format!("{} is not an integer in [{lo}, {hi}]", quote(&tok))));
                    }
                }
                return Ok(x);
            }
            Encoding::LittleEndian => false,
            Encoding::BigEndian => true,
        };
        let n = ty.size();
        let b = self.data.get(self.pos..self.pos + n).ok_or(ReadFail::End)?;
        self.pos += n;
        let mut a = [0u8; 8];
        a[..n].copy_from_slice(b);
        if big_endian {
            a[..n].reverse();
        }
        Ok(match ty {
            Scalar::I8 => a[0] as i8 as f64,
            Scalar::U8 => a[0] as f64,
            Scalar::I16 => i16::from_le_bytes([a[0], a[1]]) as f64,
            Scalar::U16 => u16::from_le_bytes([a[0], a[1]]) as f64,
            Scalar::I32 => i32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
            Scalar::U32 => u32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
            Scalar::F32 => f32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
            Scalar::F64 => f64::from_le_bytes(a),
        })
    }

    /// Pass over `count` values of type `ty`: in O(1) for binary data.
    fn skip(&mut self, ty: Scalar, count: usize) -> std::result::Result<(), ReadFail> {
        if self.encoding == Encoding::Ascii {
            return (0..count).try_for_each(|_| self.scalar(ty).map(|_| ()));
        }
        let end = count
            .checked_mul(ty.size())
            .and_then(|n| self.pos.checked_add(n))
            .filter(|&end| end <= self.data.len())
            .ok_or(ReadFail::End)?;
        self.pos = end;
        Ok(())
    }
}

pub(super) fn parse(bytes: &[u8], path: &Path) -> Result<RawMesh> {
    let header = parse_header(bytes, path)?;
    let Some(n_vertices) = header.elements.iter().find(|e| e.name == "vertex").map(|e| e.count) else {
        return Err(parse_error(path, "no 'vertex' element"));
    };
    let mut body = Body {
        data: &bytes[header.body..],
        pos: 0,
        encoding: header.encoding,
    };
    // Indices are checked against the declared vertex count as faces are read (the face
    // element may come first); the vertex element must then deliver that many.
    let mut raw = RawMesh::new(n_vertices, path)?;
    for element in &header.elements {
        read_element(element, header.encoding, &mut body, &mut raw, path)?;
    }
    check_no_data_left(&header, body, bytes, path)?;
    Ok(raw)
}

/// Where an element's properties go: the slots of `x`, `y`, `z` (vertex) and of the index
/// list (face); `usize::MAX` for none.
struct Slots {
    is_vertex: bool,
    is_face: bool,
    coord: [usize; 3],
    index: usize,
}

impl Slots {
    /// The slots of `element`; a vertex element needs `x`, `y`, `z`, a face element an
    /// index list.
    fn of(element: &Element, path: &Path) -> Result<Slots> {
        let is_vertex = element.name == "vertex";
        let is_face = element.name == "face";
        let mut coord = [usize::MAX; 3];
        let mut index = usize::MAX;
        for (k, p) in element.properties.iter().enumerate() {
            match (is_vertex, is_face, p) {
                (true, _, Property::Scalar { name, .. }) if ["x", "y", "z"].contains(&name.as_str()) => {
                    coord[(name.as_bytes()[0] - b'x') as usize] = k;
                }
                (_, true, Property::List { name, .. }) if name == "vertex_indices" || name == "vertex_index" => {
                    index = k
                }
                _ => {}
            }
        }
        if is_vertex {
            if let Some(axis) = coord.iter().position(|&s| s == usize::MAX) {
                return Err(parse_error(
                    path,
                    format!("the vertex element has no scalar property '{}'", ["x", "y", "z"][axis]),
                ));
            }
        }
        if is_face && index == usize::MAX {
            return Err(parse_error(
                path,
                "the face element has no 'vertex_indices' list property",
            ));
        }
        Ok(Slots { is_vertex, is_face, coord, index })
    }
}

/// Read every record of one element: vertex positions and faces into `raw`, other
/// elements' data skipped.
fn read_element(element: &Element, encoding: Encoding, body: &mut Body<'_>, raw: &mut RawMesh, path: &Path) -> Result<()> {
    let slots = Slots::of(element, path)?;
    let min_bytes = element.min_record_bytes(encoding, slots.index);
    if min_bytes == 0 {
        // No properties (vertex and face have some): records of zero bytes in binary
        // data, empty lines in ASCII. Nothing to read, so no loop over the count.
        if encoding == Encoding::Ascii && element.count > body.remaining().saturating_add(1) {
            return Err(parse_error(
                path,
                format!(
                    "element '{}' declares {} records (empty lines), but only {} bytes of data are left",
                    element.name,
                    element.count,
                    body.remaining()
                ),
            ));
        }
        return Ok(());
    }
    // Each record takes at least `min_bytes` (a valid one; a shorter face is an error
    // where it is read): the loop below ends within the data, and nothing is reserved
    // beyond what the data can hold.
    let fits = body.remaining() / min_bytes + 1;
    if slots.is_vertex {
        raw.reserve(element.count.min(fits), 0);
    }
    if slots.is_face {
        raw.reserve(0, element.count.min(fits));
    }
    let mut poly: Vec<u64> = Vec::new();
    for r in 0..element.count {
        let xyz = read_record(element, &slots, r, body, &mut poly, path)?;
        if slots.is_vertex {
            raw.positions.push(xyz);
        }
        if slots.is_face {
            raw.push_polygon(&poly, path, None)?;
        }
    }
    Ok(())
}

/// Read record `r` of `element`: its position (for a vertex) and its index list into
/// `poly` (for a face).
fn read_record(
    element: &Element,
    slots: &Slots,
    r: usize,
    body: &mut Body<'_>,
    poly: &mut Vec<u64>,
    path: &Path,
) -> Result<[f64; 3]> {
    let fail = |f: ReadFail, what: &str| match f {
        ReadFail::End => parse_error(
            path,
            format!(
                "the file ends in {} {r} of {} (truncated?)",
                element.name, element.count
            ),
        ),
        ReadFail::Bad(m) => parse_error(path, format!("{} {r}, {what}: {m}", element.name)),
    };
    let mut xyz = [0.0; 3];
    for (k, p) in element.properties.iter().enumerate() {
        match p {
            Property::Scalar { ty, name } => {
                let x = body.scalar(*ty).map_err(|f| fail(f, name))?;
                if let Some(axis) = slots.coord.iter().position(|&s| s == k) {
                    xyz[axis] = x;
                }
            }
            Property::List { count, item, name } => {
                let c = body.scalar(*count).map_err(|f| fail(f, name))?;
                if c < 0.0 {
                    return Err(fail(ReadFail::Bad(format!("negative list length {c}")), name));
                }
                let c = c as usize;
                if k != slots.index {
                    body.skip(*item, c).map_err(|f| fail(f, name))?;
                    continue;
                }
                poly.clear();
                for _ in 0..c {
                    let x = body.scalar(*item).map_err(|f| fail(f, name))?;
                    if x < 0.0 || x.fract() != 0.0 || x >= 2f64.powi(63) {
                        return Err(fail(
                            ReadFail::Bad(format!("vertex index {x} is not a non-negative integer")),
                            name,
                        ));
                    }
                    poly.push(x as u64);
                }
            }
        }
    }
    Ok(xyz)
}

/// Data left over means the header's counts do not describe the file.
fn check_no_data_left(header: &Header, mut body: Body<'_>, bytes: &[u8], path: &Path) -> Result<()> {
    let last = header.elements.last().map_or("end_header", |e| e.name.as_str());
    match header.encoding {
        Encoding::Ascii => {
            if let Some(tok) = body.token() {
                let start = header.body + body.pos - tok.len();
                let line = 1 + bytes[..start].iter().filter(|&&b| b == b'\n').count();
                return Err(parse_error(
                    path,
                    format!(
                        "line {line}: data after the last element '{last}': {} (do the header's counts match the data?)",
                        quote(&String::from_utf8_lossy(tok))
                    ),
                ));
            }
        }
        _ if body.remaining() > 0 => {
            return Err(parse_error(
                path,
                format!(
                    "{} bytes of data after the last element '{last}' (do the header's counts match the data?)",
                    body.remaining()
                ),
            ));
        }
        _ => {}
    }
    Ok(())
}

pub(super) fn write(
    w: &mut impl Write,
    mesh: &TriMesh,
    colors: Option<&[[u8; 3]]>,
    binary: bool,
) -> std::io::Result<()> {
    let format = if binary { "binary_little_endian" } else { "ascii" };
    let index_type = if mesh.n_vertices() > i32::MAX as usize {
        "uint"
    } else {
        "int"
    };
    writeln!(w, "ply")?;
    writeln!(w, "format {format} 1.0")?;
    writeln!(w, "comment dualspectra {}", crate::VERSION)?;
    writeln!(w, "element vertex {}", mesh.n_vertices())?;
    for c in ["x", "y", "z"] {
        writeln!(w, "property double {c}")?;
    }
    if colors.is_some() {
        for c in ["red", "green", "blue"] {
            writeln!(w, "property uchar {c}")?;
        }
    }
    writeln!(w, "element face {}", mesh.n_faces())?;
    writeln!(w, "property list uchar {index_type} vertex_indices")?;
    writeln!(w, "end_header")?;
    for (i, p) in mesh.vertices().iter().enumerate() {
        let c = colors.map(|c| c[i]);
        if binary {
            for x in p {
                w.write_all(&x.to_le_bytes())?;
            }
            if let Some(c) = c {
                w.write_all(&c)?;
            }
        } else {
            write!(w, "{:?} {:?} {:?}", p[0], p[1], p[2])?;
            if let Some(c) = c {
                write!(w, " {} {} {}", c[0], c[1], c[2])?;
            }
            writeln!(w)?;
        }
    }
    for f in mesh.faces() {
        if binary {
            w.write_all(&[3u8])?;
            for i in f {
                w.write_all(&i.to_le_bytes())?;
            }
        } else {
            writeln!(w, "3 {} {} {}", f[0], f[1], f[2])?;
        }
    }
    Ok(())
}
