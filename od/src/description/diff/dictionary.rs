//! The dictionary: objects in index order, their sub-objects, and values compared as the model holds
//! them (reals bit for bit).

use std::collections::BTreeSet;

use super::context::{bytes_text, or_none, Cx};
use super::{Change, Shown, Step};
use crate::dict::Dictionary;
use crate::object::{ObjFlags, Object, SubObject};
use crate::types::DataType;
use crate::value::Value;

pub(super) fn dictionary(cx: &mut Cx<'_>, a: &Dictionary, b: &Dictionary) {
    let indices: BTreeSet<u16> = a.objects().chain(b.objects()).map(|o| o.index).collect();
    for index in indices {
        match (a.object(index), b.object(index)) {
            (Some(x), Some(y)) => object(cx, x, y),
            (Some(x), None) => cx.push(Some(Step::Object(index)), Change::OnlyInA(x.name.clone())),
            (None, Some(y)) => cx.push(Some(Step::Object(index)), Change::OnlyInB(y.name.clone())),
            (None, None) => {}
        }
    }
}

fn object(cx: &mut Cx<'_>, a: &Object, b: &Object) {
    let Object {
        index,
        name,
        description,
        kind,
        type_name,
        subs,
        flags,
    } = a;
    let index = *index;
    let text = |v: &Option<String>| match v {
        Some(t) => Shown::Text(t.clone()),
        None => Shown::Plain("none".into()),
    };
    cx.within(Step::Object(index), |cx| {
        cx.text("name", name, &b.name);
        cx.field("description", description, &b.description, text);
        cx.plain("object code", kind, &b.kind);
        cx.field("type name", type_name, &b.type_name, text);
        cx.field("ObjFlags", flags, &b.flags, obj_flags);
    });
    let all: BTreeSet<u8> = subs.keys().chain(b.subs.keys()).copied().collect();
    for s in all {
        let step = Step::Entry(index, s);
        match (subs.get(&s), b.subs.get(&s)) {
            (Some(x), Some(y)) => cx.within(step, |cx| sub_object(cx, x, y)),
            (Some(x), None) => cx.push(Some(step), Change::OnlyInA(x.name.clone())),
            (None, Some(y)) => cx.push(Some(step), Change::OnlyInB(y.name.clone())),
            (None, None) => {}
        }
    }
}

fn sub_object(cx: &mut Cx<'_>, a: &SubObject, b: &SubObject) {
    let SubObject {
        name,
        description,
        data_type,
        bit_size,
        access,
        pdo,
        default,
        unit,
        low,
        high,
        value,
        value_set,
        value_plus_node_id,
        flags,
    } = a;
    cx.field("unit", unit, &b.unit, |u| {
        Shown::Plain(u.map_or_else(|| "none".into(), crate::units::unit_text))
    });
    cx.text("name", name, &b.name);
    cx.field("description", description, &b.description, |v| match v {
        Some(t) => Shown::Text(t.clone()),
        None => Shown::Plain("none".into()),
    });
    cx.plain("type", data_type, &b.data_type);
    // A fixed-size type's size is the type's: a change of it is the change of type already reported.
    let natural = |s: &SubObject| s.bit_size == s.data_type.bit_size();
    if !(natural(a) && natural(b)) {
        cx.field("size", bit_size, &b.bit_size, |v| {
            Shown::Plain(v.map_or_else(|| "unbounded".into(), |bits| format!("{bits} bits")))
        });
    }
    cx.field("access", access, &b.access, |acc| {
        let mut t = acc.kind.to_string();
        if let Some(r) = acc.read_states {
            t.push_str(&format!(" read:{r}"));
        }
        if let Some(w) = acc.write_states {
            t.push_str(&format!(" write:{w}"));
        }
        Shown::Plain(t)
    });
    cx.field("PDO mapping", pdo, &b.pdo, |p| {
        Shown::Plain(format!("{p:?}"))
    });
    let (ta, tb) = (*data_type, b.data_type);
    let same_default = match (default, &b.default) {
        (Some(x), Some(y)) => x.plus_node_id == y.plus_node_id && same_value(&x.value, &y.value),
        (x, y) => x.is_none() && y.is_none(),
    };
    cx.report(
        "default",
        !same_default,
        (&(ta, default), &(tb, &b.default)),
        |(t, d)| match d {
            None => Shown::Plain("none".into()),
            Some(d) if d.plus_node_id => Shown::Plain(format!("$NODEID+{}", d.value.to_text(*t))),
            Some(d) => show_value(*t, &d.value),
        },
        |(_, d)| {
            or_none(d, |d| {
                let node = if d.plus_node_id { "$NODEID+" } else { "" };
                format!("{node}{}", held(&d.value))
            })
        },
    );
    for (field, x, y) in [("low limit", low, &b.low), ("high limit", high, &b.high)] {
        let same = match (x, y) {
            (Some(x), Some(y)) => same_value(x, y),
            (x, y) => x.is_none() && y.is_none(),
        };
        cx.report(
            field,
            !same,
            (&(ta, x), &(tb, y)),
            |(t, v)| match v {
                None => Shown::Plain("none".into()),
                Some(v) => show_value(*t, v),
            },
            |(_, v)| or_none(v, held),
        );
    }
    cx.report(
        "value",
        value != &b.value,
        (&(ta, value), &(tb, &b.value)),
        |(t, v)| show_bytes(*t, v),
        |(_, v)| bytes_text(v),
    );
    let yes_no = |set: &bool| Shown::Plain(if *set { "yes" } else { "no" }.into());
    cx.field("value set", value_set, &b.value_set, yes_no);
    cx.field(
        "value relative to the node-ID",
        value_plus_node_id,
        &b.value_plus_node_id,
        yes_no,
    );
    cx.field("ObjFlags", flags, &b.flags, obj_flags);
}

/// CiA 306 `ObjFlags` as a difference shows them: `0x2 (refuse read on scan)`, `none` where the file
/// gives none.
fn obj_flags(flags: &Option<ObjFlags>) -> Shown {
    Shown::Plain(flags.map_or_else(|| "none".into(), |f| f.to_string()))
}

/// A value as the model holds it, reals by their bits.
fn held(v: &Value) -> String {
    match v {
        Value::Real32(x) => format!("Real32(0x{:08X})", x.to_bits()),
        Value::Real64(x) => format!("Real64(0x{:016X})", x.to_bits()),
        other => format!("{other:?}"),
    }
}

/// True when two values are the same, reals compared bit for bit.
fn same_value(a: &Value, b: &Value) -> bool {
    match (a, b) {
        (Value::Real32(x), Value::Real32(y)) => x.to_bits() == y.to_bits(),
        (Value::Real64(x), Value::Real64(y)) => x.to_bits() == y.to_bits(),
        _ => a == b,
    }
}

/// A value as its entry's type writes it: strings quoted, numbers as numbers, byte strings as bytes.
fn show_value(t: DataType, v: &Value) -> Shown {
    match v {
        Value::String(s) => Shown::Text(s.clone()),
        Value::Unicode(u) => Shown::Text(String::from_utf16_lossy(u)),
        Value::Bytes(b) => Shown::Plain(bytes_text(b)),
        other => Shown::Plain(other.to_text(t)),
    }
}

/// The current value's bytes as a value of its entry's type, or as bytes when they are no value of it.
fn show_bytes(t: DataType, bytes: &[u8]) -> Shown {
    match Value::decode(t, bytes) {
        Ok(v) => show_value(t, &v),
        Err(_) => Shown::Plain(format!("{} (not a {t})", bytes_text(bytes))),
    }
}
