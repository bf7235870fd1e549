//! `list`: the entries of the `--od` description, one per line (no bus needed).

use std::io::Write;

use od::dict::Address;

use crate::ToolError;

/// `list`: every entry of `desc`, in index order.
pub fn run(desc: &od::DeviceDescription, json: bool, out: &mut dyn Write) -> Result<(), ToolError> {
    let io = ToolError::Output;
    let mut rows = Vec::new();
    for o in desc.dictionary.objects() {
        for (&sub, e) in &o.subs {
            let name = if o.kind.has_subs() {
                format!("{}.{}", o.name, e.name)
            } else {
                o.name.clone()
            };
            let default = e.default.as_ref().map(|d| {
                if d.plus_node_id {
                    format!("$NODEID+{}", d.value)
                } else {
                    d.value.to_string()
                }
            });
            let limits = crate::limits_text(e);
            let addr = Address::new(o.index, sub);
            let unit = e.unit.map(od::units::unit_text);
            // What dump and apply leave out for the description's ObjFlags (CiA 306 §4.6.3).
            let flags = Some(o.flags_of(sub)).filter(|f| !f.is_empty());
            if json {
                rows.push(serde_json::json!({
                    "address": addr.to_string(),
                    "name": name,
                    "type": e.data_type.to_string(),
                    "access": e.access.kind.as_str(),
                    "default": default,
                    "limits": limits,
                    "unit": unit,
                    "obj_flags": flags.map(|f| f.bits()),
                }));
            } else {
                let mut line = format!(
                    "{addr}  {name}  {}  {}",
                    e.data_type,
                    e.access.kind.as_str()
                );
                if let Some(d) = default {
                    line.push_str(&format!("  default {d}"));
                }
                if let Some(l) = limits {
                    line.push_str(&format!("  limits {l}"));
                }
                if let Some(u) = unit {
                    line.push_str(&format!("  unit {u}"));
                }
                if let Some(f) = flags {
                    line.push_str(&format!("  ObjFlags {f}"));
                }
                writeln!(out, "{line}").map_err(io)?;
            }
        }
    }
    if json {
        writeln!(out, "{}", serde_json::json!({ "entries": rows })).map_err(io)?;
    }
    Ok(())
}
