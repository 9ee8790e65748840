//! The shape of an RTL signal's data type, as Verilator's elaboration gives it: a packed vector,
//! a packed struct or union (members, most significant first), a packed or an unpacked array.
//! From it, a map's name below a signal (`cfg_q.pw`, `sign_q[0]`, `mem[2][7:4]`) is resolved to
//! the bits it names ([`Shape::select`]), and `pmu50 rtl-map` lists the fields a signal holds
//! ([`Shape::fields`]).

/// A data type, resolved (type references followed, enums as their base type).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Shape {
    /// A packed vector `[left:right]` (a single bit: `[0:0]`).
    Bits { left: i64, right: i64 },
    /// A packed struct (`union` false) or union: its members, the first the most significant.
    Struct {
        name: String,
        union: bool,
        members: Vec<(String, Shape)>,
    },
    /// A packed array `[left:right]` of elements.
    Packed {
        left: i64,
        right: i64,
        elem: Box<Shape>,
    },
    /// An unpacked array `[left:right]` of elements (each stored apart).
    Unpacked {
        left: i64,
        right: i64,
        elem: Box<Shape>,
    },
    /// A type the kit does not read (a string, a real, a class).
    Other(String),
}

/// The bits a name selects: the unpacked elements on the way (storage indices, from 0), then a
/// bit range of the packed value there.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Selection {
    pub elements: Vec<u32>,
    pub lsb: u32,
    pub width: u32,
    /// The selected part's shape.
    pub shape: Shape,
}

fn span(left: i64, right: i64) -> u32 {
    (left - right).unsigned_abs() as u32 + 1
}

/// The offset from the least significant end of index `i` of a range `[left:right]`, or None
/// outside it.
fn offset(left: i64, right: i64, i: i64) -> Option<u32> {
    let (lo, hi) = (left.min(right), left.max(right));
    if !(lo..=hi).contains(&i) {
        return None;
    }
    Some(if left >= right { i - right } else { right - i } as u32)
}

impl Shape {
    /// A single bit.
    pub fn bit() -> Shape {
        Shape::Bits { left: 0, right: 0 }
    }

    /// The packed width in bits (0 for an unpacked array or a type the kit does not read).
    pub fn width(&self) -> u32 {
        match self {
            Shape::Bits { left, right } => span(*left, *right),
            Shape::Struct { union, members, .. } => {
                let w = members.iter().map(|(_, m)| m.width());
                if *union {
                    w.max().unwrap_or(0)
                } else {
                    w.sum()
                }
            }
            Shape::Packed { left, right, elem } => span(*left, *right) * elem.width(),
            Shape::Unpacked { .. } | Shape::Other(_) => 0,
        }
    }

    /// `cfg_t`, `logic [15:0]`, `logic [3:0] [0:2]` for a message.
    pub fn describe(&self) -> String {
        match self {
            Shape::Bits { left, right } if left == right && *left == 0 => "logic".into(),
            Shape::Bits { left, right } => format!("logic [{left}:{right}]"),
            Shape::Struct { name, union, .. } => format!(
                "{} {}",
                if *union { "union" } else { "struct" },
                name.rsplit("::").next().unwrap_or(name)
            ),
            Shape::Packed { left, right, elem } => format!("{} [{left}:{right}]", elem.describe()),
            Shape::Unpacked { left, right, elem } => {
                format!("{} (unpacked [{left}:{right}])", elem.describe())
            }
            Shape::Other(n) => n.clone(),
        }
    }

    /// Resolve `rest` (what follows a signal's name: `.field`, `[i]`, `[hi:lo]`, in any
    /// sequence) to the bits it selects. The error says what is valid there.
    pub fn select(&self, rest: &str) -> Result<Selection, String> {
        let mut sel = Selection {
            elements: Vec::new(),
            lsb: 0,
            width: self.width(),
            shape: self.clone(),
        };
        let mut s = rest;
        while !s.is_empty() {
            if let Some(r) = s.strip_prefix('.') {
                let end = r.find(['.', '[']).unwrap_or(r.len());
                let (name, tail) = r.split_at(end);
                let Shape::Struct { members, union, .. } = &sel.shape else {
                    return Err(format!(
                        "`.{name}`: a {} has no fields",
                        sel.shape.describe()
                    ));
                };
                let Some(k) = members.iter().position(|(n, _)| n == name) else {
                    let names: Vec<&str> = members.iter().map(|(n, _)| n.as_str()).collect();
                    return Err(format!(
                        "{} has no field `{name}` (its fields: {})",
                        sel.shape.describe(),
                        names.join(", ")
                    ));
                };
                let below: u32 = if *union {
                    0
                } else {
                    members[k + 1..].iter().map(|(_, m)| m.width()).sum()
                };
                let m = members[k].1.clone();
                sel.lsb += below;
                sel.width = m.width();
                sel.shape = m;
                s = tail;
            } else if let Some(r) = s.strip_prefix('[') {
                let end = r
                    .find(']')
                    .ok_or_else(|| format!("`[{r}`: no closing `]`"))?;
                let inside = &r[..end];
                s = &r[end + 1..];
                let num = |t: &str| -> Result<i64, String> {
                    t.trim()
                        .parse::<i64>()
                        .map_err(|_| format!("`[{inside}]`: an index is a decimal number"))
                };
                let range = |left: i64, right: i64| format!("[{}:{}]", left, right);
                match (&sel.shape, inside.split_once(':')) {
                    (Shape::Unpacked { left, right, elem }, None) => {
                        let i = num(inside)?;
                        if offset(*left, *right, i).is_none() {
                            return Err(format!(
                                "index {i} is outside the unpacked range {}",
                                range(*left, *right)
                            ));
                        }
                        // Verilator stores element i at i - (the range's low end)
                        sel.elements.push((i - left.min(right)) as u32);
                        sel.lsb = 0;
                        sel.width = elem.width();
                        sel.shape = (**elem).clone();
                    }
                    (Shape::Packed { left, right, elem }, None) => {
                        let i = num(inside)?;
                        let o = offset(*left, *right, i).ok_or_else(|| {
                            format!("index {i} is outside {}", range(*left, *right))
                        })?;
                        sel.lsb += o * elem.width();
                        sel.width = elem.width();
                        sel.shape = (**elem).clone();
                    }
                    (Shape::Bits { left, right }, None) => {
                        let i = num(inside)?;
                        let o = offset(*left, *right, i).ok_or_else(|| {
                            format!("bit {i} is outside {}", range(*left, *right))
                        })?;
                        sel.lsb += o;
                        sel.width = 1;
                        sel.shape = Shape::bit();
                    }
                    (Shape::Bits { left, right }, Some((h, l))) => {
                        let (h, l) = (num(h)?, num(l)?);
                        let (oh, ol) = match (offset(*left, *right, h), offset(*left, *right, l)) {
                            (Some(a), Some(b)) if a >= b => (a, b),
                            _ => {
                                return Err(format!(
                                    "[{h}:{l}] is not a part of {}, most significant first",
                                    range(*left, *right)
                                ))
                            }
                        };
                        sel.lsb += ol;
                        sel.width = oh - ol + 1;
                        sel.shape = Shape::Bits {
                            left: i64::from(oh - ol),
                            right: 0,
                        };
                    }
                    (other, _) => {
                        return Err(format!(
                            "`[{inside}]`: a {} has no such index",
                            other.describe()
                        ))
                    }
                }
            } else {
                return Err(format!("`{s}`: expected `.field` or `[index]`"));
            }
        }
        if matches!(sel.shape, Shape::Unpacked { .. }) {
            return Err(format!(
                "{} is an unpacked array: name an element (`[i]`)",
                sel.shape.describe()
            ));
        }
        Ok(sel)
    }

    /// The fields of a packed struct, recursively, as (`.a.b`, lsb, width), most significant
    /// first; and the elements of an unpacked array of at most `max_elems` elements
    /// (`[i]...`). A vector has none.
    pub fn fields(&self, max_elems: u32) -> Vec<(String, Selection)> {
        let mut out = Vec::new();
        let mut walk = |suffix: String| {
            if let Ok(sel) = self.select(&suffix) {
                out.push((suffix, sel));
            }
        };
        fn names(s: &Shape, prefix: &str, max: u32, out: &mut Vec<String>) {
            match s {
                Shape::Struct { members, .. } => {
                    for (n, m) in members {
                        let p = format!("{prefix}.{n}");
                        out.push(p.clone());
                        names(m, &p, max, out);
                    }
                }
                Shape::Unpacked { left, right, elem } if span(*left, *right) <= max => {
                    let (lo, hi) = (*left.min(right), *left.max(right));
                    for i in lo..=hi {
                        let p = format!("{prefix}[{i}]");
                        out.push(p.clone());
                        names(elem, &p, max, out);
                    }
                }
                Shape::Packed { left, right, elem }
                    if span(*left, *right) <= max && matches!(**elem, Shape::Struct { .. }) =>
                {
                    let (lo, hi) = (*left.min(right), *left.max(right));
                    for i in lo..=hi {
                        let p = format!("{prefix}[{i}]");
                        out.push(p.clone());
                        names(elem, &p, max, out);
                    }
                }
                _ => {}
            }
        }
        let mut v = Vec::new();
        names(self, "", max_elems, &mut v);
        for n in v {
            walk(n);
        }
        out
    }
}

/// Split `pmu50.u.cfg_q.pw[3]` where the signal's name ends: the longest prefix, at a `.` or a
/// `[`, for which `is_signal` holds; the prefix and what follows it.
pub fn split_signal(path: &str, is_signal: impl Fn(&str) -> bool) -> Option<(&str, &str)> {
    let mut cuts: Vec<usize> = path
        .char_indices()
        .filter(|(_, c)| *c == '.' || *c == '[')
        .map(|(i, _)| i)
        .collect();
    cuts.push(path.len());
    cuts.into_iter()
        .rev()
        .map(|i| path.split_at(i))
        .find(|(p, _)| is_signal(p))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bits(w: i64) -> Shape {
        Shape::Bits {
            left: w - 1,
            right: 0,
        }
    }

    /// `struct packed { logic adaptive; logic [15:0] pw; logic [7:0] cth; }`
    fn cfg() -> Shape {
        Shape::Struct {
            name: "pkg::cfg_t".into(),
            union: false,
            members: vec![
                ("adaptive".into(), Shape::bit()),
                ("pw".into(), bits(16)),
                ("cth".into(), bits(8)),
            ],
        }
    }

    #[test]
    fn a_field_of_a_packed_struct_is_its_bits_counted_from_the_last_member() {
        let c = cfg();
        assert_eq!(c.width(), 25);
        let pw = c.select(".pw").unwrap();
        assert_eq!((pw.lsb, pw.width), (8, 16));
        let a = c.select(".adaptive").unwrap();
        assert_eq!((a.lsb, a.width), (24, 1));
        let b = c.select(".pw[15:8]").unwrap();
        assert_eq!((b.lsb, b.width), (16, 8));
        let e = c.select(".pww").unwrap_err();
        assert!(
            e.contains("no field `pww`") && e.contains("adaptive, pw, cth"),
            "{e}"
        );
        assert!(c.select("[3]").unwrap_err().contains("no such index"));
        let names: Vec<String> = c.fields(8).into_iter().map(|(n, _)| n).collect();
        assert_eq!(names, [".adaptive", ".pw", ".cth"]);
    }

    #[test]
    fn array_elements_and_bits_follow_the_declared_ranges() {
        let v = bits(2);
        assert_eq!(v.select("[1]").unwrap().lsb, 1);
        assert!(v.select("[2]").unwrap_err().contains("outside [1:0]"));
        let asc = Shape::Bits { left: 0, right: 7 };
        assert_eq!(asc.select("[0]").unwrap().lsb, 7);
        let packed = Shape::Packed {
            left: 1,
            right: 0,
            elem: Box::new(cfg()),
        };
        assert_eq!(packed.width(), 50);
        let s = packed.select("[1].cth").unwrap();
        assert_eq!((s.lsb, s.width), (25, 8));
        let mem = Shape::Unpacked {
            left: 3,
            right: 1,
            elem: Box::new(bits(8)),
        };
        let s = mem.select("[3][7:4]").unwrap();
        assert_eq!((s.elements.clone(), s.lsb, s.width), (vec![2], 4, 4));
        assert!(mem.select("").unwrap_err().contains("name an element"));
        assert!(mem
            .select("[0]")
            .unwrap_err()
            .contains("outside the unpacked range [3:1]"));
    }

    #[test]
    fn the_signal_is_the_longest_known_prefix() {
        let known = ["pmu50.u.cfg_q", "pmu50.u"];
        let f = |p: &str| known.contains(&p);
        assert_eq!(
            split_signal("pmu50.u.cfg_q.pw[3]", f),
            Some(("pmu50.u.cfg_q", ".pw[3]"))
        );
        assert_eq!(split_signal("pmu50.u", f), Some(("pmu50.u", "")));
        assert_eq!(split_signal("pmu50.v.x", f), None);
    }
}
