//! Stanford PLY reader and writer: `ascii`, `binary_little_endian` and
//! `binary_big_endian` 1.0, all eight scalar types under both their names (`char` /
//! `int8`, ..., `double` / `float64`).
//!
//! Read: the `vertex` element's `x`, `y`, `z` (any scalar type) and the `face`
//! element's `vertex_indices` (or `vertex_index`) list; every other element and
//! property is read past and ignored, so files with normals, colours, `edge` or
//! `material` elements load. Elements may come in any order.
//!
//! Written here rather than with `ply-rs` (last release 2018, no typed errors for
//! truncated binary data): the format is small, and owning the reader gives messages
//! that name the element and record where a file is cut or malformed.

use super::{parse_error, RawMesh};
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

struct Header {
    encoding: Encoding,
    elements: Vec<Element>,
    /// Byte offset of the first data byte.
    body: usize,
}

fn parse_header(bytes: &[u8], path: &Path) -> Result<Header> {
    let bad = |line: usize, m: String| parse_error(path, format!("line {line}: bad header: {m}"));
    let mut pos = 0;
    let mut line_no = 0;
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
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
                return Err(bad(1, format!("first line must be 'ply', found '{}'", truncate(line))));
            }
            continue;
        }
        let t: Vec<&str> = line.split_whitespace().collect();
        match t.first().copied() {
            None | Some("comment") | Some("obj_info") => {}
            Some("format") => {
                encoding = Some(match (t.get(1).copied(), t.get(2).copied()) {
                    (Some("ascii"), Some("1.0")) => Encoding::Ascii,
                    (Some("binary_little_endian"), Some("1.0")) => Encoding::LittleEndian,
                    (Some("binary_big_endian"), Some("1.0")) => Encoding::BigEndian,
                    _ => return Err(bad(line_no, format!("unsupported format line '{line}'"))),
                });
            }
            Some("element") => {
                let (Some(name), Some(count)) = (t.get(1), t.get(2).and_then(|c| c.parse::<usize>().ok())) else {
                    return Err(bad(
                        line_no,
                        format!("expected 'element <name> <count>', found '{line}'"),
                    ));
                };
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
                        .ok_or_else(|| bad(line_no, format!("unknown property type in '{line}'")))
                };
                let property = if t.get(1) == Some(&"list") {
                    let (count, item) = (ty(2)?, ty(3)?);
                    let name = t
                        .get(4)
                        .ok_or_else(|| bad(line_no, format!("list property without a name: '{line}'")))?;
                    if !count.is_integer() {
                        return Err(bad(
                            line_no,
                            format!("list count type must be an integer type: '{line}'"),
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
                        .ok_or_else(|| bad(line_no, format!("property without a name: '{line}'")))?;
                    Property::Scalar {
                        ty,
                        name: name.to_string(),
                    }
                };
                element.properties.push(property);
            }
            Some("end_header") => break,
            Some(other) => return Err(bad(line_no, format!("unknown keyword '{}'", truncate(other)))),
        }
    }
    let encoding = encoding.ok_or_else(|| parse_error(path, "bad header: no 'format' line"))?;
    Ok(Header {
        encoding,
        elements,
        body: pos,
    })
}

fn truncate(s: &str) -> String {
    s.chars().take(40).collect()
}

/// The data section, read one scalar at a time as `f64` (exact for every PLY type).
enum Body<'a> {
    Ascii(std::str::SplitAsciiWhitespace<'a>),
    Binary {
        data: &'a [u8],
        pos: usize,
        big_endian: bool,
    },
}

enum ReadFail {
    End,
    Bad(String),
}

impl Body<'_> {
    fn scalar(&mut self, ty: Scalar) -> std::result::Result<f64, ReadFail> {
        match self {
            Body::Ascii(tokens) => {
                let tok = tokens.next().ok_or(ReadFail::End)?;
                let x: f64 = tok
                    .parse()
                    .map_err(|_| ReadFail::Bad(format!("'{}' is not a number", truncate(tok))))?;
                if ty.is_integer() && x.fract() != 0.0 {
                    return Err(ReadFail::Bad(format!("'{tok}' is not an integer")));
                }
                Ok(x)
            }
            Body::Binary { data, pos, big_endian } => {
                let n = ty.size();
                let b = data.get(*pos..*pos + n).ok_or(ReadFail::End)?;
                *pos += n;
                let mut a = [0u8; 8];
                a[..n].copy_from_slice(b);
                if *big_endian {
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
        }
    }
}

pub(super) fn parse(bytes: &[u8], path: &Path) -> Result<RawMesh> {
    let header = parse_header(bytes, path)?;
    let data = &bytes[header.body..];
    let mut body = match header.encoding {
        Encoding::Ascii => Body::Ascii(
            std::str::from_utf8(data)
                .map_err(|_| parse_error(path, "ASCII PLY data is not text (binary data under 'format ascii'?)"))?
                .split_ascii_whitespace(),
        ),
        Encoding::LittleEndian => Body::Binary {
            data,
            pos: 0,
            big_endian: false,
        },
        Encoding::BigEndian => Body::Binary {
            data,
            pos: 0,
            big_endian: true,
        },
    };
    let mut raw = RawMesh::new();
    let mut seen_vertex = false;
    for element in &header.elements {
        let is_vertex = element.name == "vertex";
        let is_face = element.name == "face";
        let mut coord_slot = [usize::MAX; 3];
        let mut index_slot = usize::MAX;
        for (k, p) in element.properties.iter().enumerate() {
            match (is_vertex, is_face, p) {
                (true, _, Property::Scalar { name, .. }) if ["x", "y", "z"].contains(&name.as_str()) => {
                    coord_slot[(name.as_bytes()[0] - b'x') as usize] = k;
                }
                (_, true, Property::List { name, .. }) if name == "vertex_indices" || name == "vertex_index" => {
                    index_slot = k
                }
                _ => {}
            }
        }
        if is_vertex {
            if let Some(axis) = coord_slot.iter().position(|&s| s == usize::MAX) {
                return Err(parse_error(
                    path,
                    format!("the vertex element has no scalar property '{}'", ["x", "y", "z"][axis]),
                ));
            }
            seen_vertex = true;
            raw.positions.reserve(element.count.min(1 << 24));
        }
        if is_face {
            if index_slot == usize::MAX {
                return Err(parse_error(
                    path,
                    "the face element has no 'vertex_indices' list property",
                ));
            }
            raw.offsets.reserve(element.count.min(1 << 24));
        }
        for r in 0..element.count {
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
                        if let Some(axis) = coord_slot.iter().position(|&s| s == k) {
                            xyz[axis] = x;
                        }
                    }
                    Property::List { count, item, name } => {
                        let c = body.scalar(*count).map_err(|f| fail(f, name))?;
                        if c < 0.0 {
                            return Err(fail(ReadFail::Bad(format!("negative list length {c}")), name));
                        }
                        let c = c as usize;
                        for _ in 0..c {
                            let x = body.scalar(*item).map_err(|f| fail(f, name))?;
                            if k == index_slot {
                                if x < 0.0 || x.fract() != 0.0 || x >= 2f64.powi(63) {
                                    return Err(fail(
                                        ReadFail::Bad(format!("vertex index {x} is not a non-negative integer")),
                                        name,
                                    ));
                                }
                                raw.indices.push(x as u64);
                            }
                        }
                    }
                }
            }
            if is_vertex {
                raw.positions.push(xyz);
            }
            if is_face {
                raw.end_polygon();
            }
        }
    }
    if !seen_vertex {
        return Err(parse_error(path, "no 'vertex' element"));
    }
    Ok(raw)
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
