//! Object-level differences between two dictionaries: objects and sub-objects that only one side has, and
//! for those both have, each attribute that differs (name, object code, type, access, PDO mapping,
//! default, limits, capacity, current value).

use std::fmt;

use crate::dict::Dictionary;
use crate::object::{DefaultValue, Object, SubObject};
use crate::value::Value;

/// One difference between dictionary `a` and dictionary `b`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Difference {
    /// An object only `a` has.
    OnlyInA {
        /// Index.
        index: u16,
        /// Its name.
        name: String,
    },
    /// An object only `b` has.
    OnlyInB {
        /// Index.
        index: u16,
        /// Its name.
        name: String,
    },
    /// A sub-object only `a` has.
    SubOnlyInA {
        /// Index.
        index: u16,
        /// Sub-index.
        sub: u8,
        /// Its name.
        name: String,
    },
    /// A sub-object only `b` has.
    SubOnlyInB {
        /// Index.
        index: u16,
        /// Sub-index.
        sub: u8,
        /// Its name.
        name: String,
    },
    /// An attribute of an object (`sub` = `None`) or sub-object that differs.
    Changed {
        /// Index.
        index: u16,
        /// Sub-index, or `None` for an attribute of the object itself.
        sub: Option<u8>,
        /// The attribute: `name`, `object code`, `type`, `access`, `PDO mapping`, `default`, `low limit`,
        /// `high limit`, `size`, `value`.
        field: &'static str,
        /// The value in `a`, as text.
        a: String,
        /// The value in `b`, as text.
        b: String,
    },
}

impl fmt::Display for Difference {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Difference::OnlyInA { index, name } => write!(f, "- 0x{index:04X} {name}"),
            Difference::OnlyInB { index, name } => write!(f, "+ 0x{index:04X} {name}"),
            Difference::SubOnlyInA { index, sub, name } => {
                write!(f, "- 0x{index:04X}:{sub:02X} {name}")
            }
            Difference::SubOnlyInB { index, sub, name } => {
                write!(f, "+ 0x{index:04X}:{sub:02X} {name}")
            }
            Difference::Changed {
                index,
                sub: None,
                field,
                a,
                b,
            } => {
                write!(f, "~ 0x{index:04X} {field}: {a} -> {b}")
            }
            Difference::Changed {
                index,
                sub: Some(s),
                field,
                a,
                b,
            } => {
                write!(f, "~ 0x{index:04X}:{s:02X} {field}: {a} -> {b}")
            }
        }
    }
}

/// Every difference between `a` and `b`, in index order. Empty when the dictionaries are equal in every
/// attribute compared.
pub fn diff(a: &Dictionary, b: &Dictionary) -> Vec<Difference> {
    let mut out = Vec::new();
    let mut ai = a.objects().peekable();
    let mut bi = b.objects().peekable();
    loop {
        match (ai.peek(), bi.peek()) {
            (None, None) => break,
            (Some(x), None) => {
                out.push(Difference::OnlyInA {
                    index: x.index,
                    name: x.name.clone(),
                });
                ai.next();
            }
            (None, Some(y)) => {
                out.push(Difference::OnlyInB {
                    index: y.index,
                    name: y.name.clone(),
                });
                bi.next();
            }
            (Some(x), Some(y)) if x.index < y.index => {
                out.push(Difference::OnlyInA {
                    index: x.index,
                    name: x.name.clone(),
                });
                ai.next();
            }
            (Some(x), Some(y)) if x.index > y.index => {
                out.push(Difference::OnlyInB {
                    index: y.index,
                    name: y.name.clone(),
                });
                bi.next();
            }
            (Some(x), Some(y)) => {
                diff_objects(x, y, &mut out);
                ai.next();
                bi.next();
            }
        }
    }
    out
}

fn diff_objects(a: &Object, b: &Object, out: &mut Vec<Difference>) {
    let index = a.index;
    let mut changed = |sub: Option<u8>, field: &'static str, x: String, y: String| {
        if x != y {
            out.push(Difference::Changed {
                index,
                sub,
                field,
                a: x,
                b: y,
            });
        }
    };
    changed(None, "name", a.name.clone(), b.name.clone());
    changed(None, "object code", a.kind.to_string(), b.kind.to_string());
    let subs: std::collections::BTreeSet<u8> =
        a.subs.keys().chain(b.subs.keys()).copied().collect();
    for s in subs {
        match (a.subs.get(&s), b.subs.get(&s)) {
            (Some(x), Some(y)) => diff_subs(index, s, x, y, out),
            (Some(x), None) => out.push(Difference::SubOnlyInA {
                index,
                sub: s,
                name: x.name.clone(),
            }),
            (None, Some(y)) => out.push(Difference::SubOnlyInB {
                index,
                sub: s,
                name: y.name.clone(),
            }),
            (None, None) => {}
        }
    }
}

fn diff_subs(index: u16, sub: u8, a: &SubObject, b: &SubObject, out: &mut Vec<Difference>) {
    let mut changed = |field: &'static str, x: String, y: String| {
        if x != y {
            out.push(Difference::Changed {
                index,
                sub: Some(sub),
                field,
                a: x,
                b: y,
            });
        }
    };
    changed("name", a.name.clone(), b.name.clone());
    changed("type", a.data_type.to_string(), b.data_type.to_string());
    changed("access", access_text(a), access_text(b));
    changed(
        "PDO mapping",
        format!("{:?}", a.pdo),
        format!("{:?}", b.pdo),
    );
    changed(
        "default",
        default_text(a, a.default.as_ref()),
        default_text(b, b.default.as_ref()),
    );
    changed(
        "low limit",
        limit_text(a, a.low.as_ref()),
        limit_text(b, b.low.as_ref()),
    );
    changed(
        "high limit",
        limit_text(a, a.high.as_ref()),
        limit_text(b, b.high.as_ref()),
    );
    if a.data_type.is_variable() || b.data_type.is_variable() {
        let size = |s: &SubObject| {
            s.bit_size
                .map_or("unbounded".to_string(), |b| format!("{b} bits"))
        };
        changed("size", size(a), size(b));
    }
    changed("value", hex(&a.value), hex(&b.value));
}

fn access_text(s: &SubObject) -> String {
    let mut t = s.access.kind.to_string();
    if let Some(r) = s.access.read_states {
        t.push_str(&format!(" read:{r}"));
    }
    if let Some(w) = s.access.write_states {
        t.push_str(&format!(" write:{w}"));
    }
    t
}

fn default_text(s: &SubObject, d: Option<&DefaultValue>) -> String {
    match d {
        None => "none".into(),
        Some(d) if d.plus_node_id => format!("$NODEID+{}", d.value.to_text(s.data_type)),
        Some(d) => d.value.to_text(s.data_type),
    }
}

fn limit_text(s: &SubObject, v: Option<&Value>) -> String {
    v.map_or("none".into(), |v| v.to_text(s.data_type))
}

fn hex(bytes: &[u8]) -> String {
    if bytes.is_empty() {
        return "(empty)".into();
    }
    bytes
        .iter()
        .map(|b| format!("{b:02X}"))
        .collect::<Vec<_>>()
        .join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::object::{AccessType, ObjectKind};
    use crate::types::DataType;

    fn base() -> Dictionary {
        let mut d = Dictionary::new();
        d.insert(Object::var(
            0x1000,
            SubObject::new("Device type", DataType::Unsigned32, AccessType::Ro),
        ));
        d.insert(
            Object::structured(0x1018, "Identity", ObjectKind::Record)
                .with_sub(
                    0,
                    SubObject::new("n", DataType::Unsigned8, AccessType::Ro)
                        .with_default(Value::Uint(1)),
                )
                .with_sub(
                    1,
                    SubObject::new("Vendor-ID", DataType::Unsigned32, AccessType::Ro),
                ),
        );
        d
    }

    #[test]
    fn equal_dictionaries_have_no_difference() {
        assert!(diff(&base(), &base()).is_empty());
    }

    #[test]
    fn every_kind_of_difference_is_reported_in_index_order() {
        let a = base();
        let mut b = base();
        b.remove(0x1000);
        b.insert(Object::var(
            0x2000,
            SubObject::new("Extra", DataType::Integer8, AccessType::Rw),
        ));
        let o = b.object_mut(0x1018).unwrap();
        o.subs.get_mut(&1).unwrap().access = AccessType::Rw.into();
        o.subs.insert(
            2,
            SubObject::new("Product code", DataType::Unsigned32, AccessType::Ro),
        );
        let text: Vec<String> = diff(&a, &b).iter().map(|d| d.to_string()).collect();
        assert_eq!(
            text,
            vec![
                "- 0x1000 Device type",
                "~ 0x1018:01 access: ro -> rw",
                "+ 0x1018:02 Product code",
                "+ 0x2000 Extra",
            ]
        );
    }
}
