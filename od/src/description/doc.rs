//! A Markdown reference of a device description: identity, one table row per entry of the dictionary
//! (address, name, type, access, PDO mapping, default, limits, meaning), and the EtherCAT parts.

use std::fmt::Write;

use crate::device::DeviceDescription;
use crate::object::{Object, PdoMapping, SubObject};

/// Writes the Markdown reference of `desc`. The output is deterministic.
pub fn write(desc: &DeviceDescription) -> String {
    let mut out = String::new();
    let id = &desc.identity;
    let title = if id.product_name.is_empty() {
        "Device"
    } else {
        id.product_name.as_str()
    };
    let _ = writeln!(out, "# {}\n", cell(title));
    let _ = writeln!(out, "| | |\n|---|---|");
    let _ = writeln!(
        out,
        "| Vendor | {} (0x{:08X}) |",
        cell(&id.vendor_name),
        id.vendor_id
    );
    if !id.order_code.is_empty() {
        let _ = writeln!(out, "| Type | {} |", cell(&id.order_code));
    }
    let _ = writeln!(out, "| Product code | 0x{:08X} |", id.product_code);
    let _ = writeln!(out, "| Revision | 0x{:08X} |", id.revision);
    let _ = writeln!(out, "| Objects | {} |", desc.dictionary.len());
    if let Some(c) = &desc.commissioning {
        match c.node_id {
            Some(id) => {
                let _ = writeln!(out, "| Node-ID | {id} |");
            }
            None => {
                let _ = writeln!(out, "| Node-ID | unconfigured |");
            }
        }
    }
    out.push('\n');

    let _ = writeln!(out, "## Object dictionary\n");
    let _ = writeln!(
        out,
        "| Index | Sub | Name | Object | Type | Access | PDO | Default | Range | Meaning |"
    );
    let _ = writeln!(out, "|---|---|---|---|---|---|---|---|---|---|");
    for object in desc.dictionary.objects() {
        if object.kind.has_subs() {
            let _ = writeln!(
                out,
                "| 0x{:04X} | | **{}** | {} | {} | | | | | {} |",
                object.index,
                cell(&object.name),
                object.kind,
                cell(object.type_name.as_deref().unwrap_or("")),
                cell(object.description.as_deref().unwrap_or(""))
            );
            for (&sub, entry) in &object.subs {
                row(&mut out, object, Some(sub), entry);
            }
        } else if let Some(entry) = object.subs.get(&0) {
            row(&mut out, object, None, entry);
        }
    }

    if let Some(ec) = &desc.ethercat {
        let _ = writeln!(out, "\n## EtherCAT\n");
        if !ec.sync_managers.is_empty() {
            let _ = writeln!(out, "| Sync manager | Kind | Start | Size | Control | Enable |\n|---|---|---|---|---|---|");
            for (i, sm) in ec.sync_managers.iter().enumerate() {
                let _ = writeln!(
                    out,
                    "| SM{i} | {} | 0x{:04X} | {} | 0x{:02X} | {} |",
                    cell(&sm.kind),
                    sm.start_address,
                    sm.default_size.map_or(String::new(), |s| s.to_string()),
                    sm.control_byte,
                    sm.enable
                );
            }
            out.push('\n');
        }
        for (dir, pdos) in [("RxPDO", &ec.rx_pdos), ("TxPDO", &ec.tx_pdos)] {
            for pdo in pdos {
                let _ = writeln!(
                    out,
                    "### {dir} 0x{:04X} {}{}\n",
                    pdo.index,
                    cell(&pdo.name),
                    pdo.sm.map_or(String::new(), |s| format!(" (SM{s})"))
                );
                let _ = writeln!(out, "| Entry | Bits | Name | Type |\n|---|---|---|---|");
                for e in &pdo.entries {
                    let _ = writeln!(
                        out,
                        "| 0x{:04X}:{:02X} | {} | {} | {} |",
                        e.index,
                        e.sub,
                        e.bit_len,
                        cell(&e.name),
                        cell(&e.data_type)
                    );
                }
                out.push('\n');
            }
        }
        if !ec.op_modes.is_empty() {
            let _ = writeln!(
                out,
                "| Op mode | Description | AssignActivate | SYNC0 cycle (ns) |\n|---|---|---|---|"
            );
            for m in &ec.op_modes {
                let _ = writeln!(
                    out,
                    "| {} | {} | 0x{:04X} | {} |",
                    cell(&m.name),
                    cell(&m.desc),
                    m.assign_activate,
                    m.cycle_time_sync0
                        .map_or(String::new(), |(t, _)| t.to_string())
                );
            }
        }
    }
    out
}

/// The row of one entry: of a sub-index of `object`, or (`sub` none) of a VAR or DOMAIN as a whole,
/// with the object's name, kind and description.
fn row(out: &mut String, object: &Object, sub: Option<u8>, entry: &SubObject) {
    let index = object.index;
    let (sub_text, name, kind, object_description) = match sub {
        Some(sub) => (format!("{sub:02X}"), &entry.name, "", None),
        None => (
            String::new(),
            &object.name,
            object.kind.name(),
            object.description.as_deref(),
        ),
    };
    let default = entry.default.as_ref().map_or(String::new(), |d| {
        let text = d.value.to_text(entry.data_type);
        if d.plus_node_id {
            format!("$NODEID+{text}")
        } else {
            text
        }
    });
    let range = match (&entry.low, &entry.high) {
        (None, None) => String::new(),
        (lo, hi) => format!(
            "{} … {}",
            lo.as_ref()
                .map_or(String::new(), |v| v.to_text(entry.data_type)),
            hi.as_ref()
                .map_or(String::new(), |v| v.to_text(entry.data_type))
        ),
    };
    let pdo = match entry.pdo {
        PdoMapping::None => "",
        PdoMapping::Rpdo => "RPDO",
        PdoMapping::Tpdo => "TPDO",
        PdoMapping::Both => "RPDO/TPDO",
    };
    let mut access = entry.access.kind.to_string();
    if let Some(s) = entry.access.write_states {
        let _ = write!(access, " (write {s})");
    }
    // CiA 306 §4.6.3: what a configuration tool leaves out for the entry.
    let flags = object.flags_of(sub.unwrap_or(0));
    if !flags.is_empty() {
        let _ = write!(access, ", ObjFlags {flags}");
    }
    let meaning = entry
        .description
        .as_deref()
        .or(object_description)
        .unwrap_or("");
    let _ = writeln!(
        out,
        "| 0x{index:04X} | {sub_text} | {} | {kind} | {} | {} | {pdo} | {} | {} | {} |",
        cell(name),
        entry.data_type,
        access,
        cell(&default),
        cell(&range),
        cell(meaning)
    );
}

/// Text made safe for one table cell.
fn cell(text: &str) -> String {
    text.replace('|', "\\|").replace(['\r', '\n'], " ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::object::{AccessType, ObjFlags, ObjectKind};
    use crate::types::DataType;
    use crate::value::Value;

    #[test]
    fn one_row_per_entry_with_default_range_and_meaning() {
        let mut desc = DeviceDescription::default();
        desc.identity.product_name = "Demo".into();
        desc.identity.vendor_id = 0x42;
        desc.dictionary.insert(
            Object::structured(0x8010, "Configuration Data", ObjectKind::Record)
                .with_sub(
                    0,
                    SubObject::new("SubIndex 000", DataType::Unsigned8, AccessType::Ro)
                        .with_default(Value::Uint(1)),
                )
                .with_sub(
                    1,
                    SubObject::new("Speed", DataType::Integer32, AccessType::Rw)
                        .with_default(Value::Int(-5))
                        .with_limits(Some(Value::Int(-10)), Some(Value::Int(10)))
                        .with_description("steps/s | signed"),
                ),
        );
        let md = write(&desc);
        assert!(md.starts_with("# Demo\n"));
        assert!(md.contains("| Vendor |  (0x00000042) |"));
        assert!(md.contains("| 0x8010 | | **Configuration Data** | RECORD |"));
        assert!(md.contains("| 0x8010 | 01 | Speed |  | INTEGER32 | rw |  | -5 | -10 … 10 | steps/s \\| signed |"), "{md}");
    }

    /// An entry's `ObjFlags` (an object's reach its entries) follow its access, in words.
    #[test]
    fn object_flags_follow_the_access() {
        let mut desc = DeviceDescription::default();
        let mut record = Object::structured(0x2000, "Calibration", ObjectKind::Record)
            .with_sub(
                0,
                SubObject::new("Count", DataType::Unsigned8, AccessType::Ro),
            )
            .with_sub(
                1,
                SubObject::new("Gain", DataType::Unsigned32, AccessType::Rw),
            );
        record.flags = Some(ObjFlags::from_bits(1));
        record.subs.get_mut(&1).unwrap().flags = Some(ObjFlags::from_bits(2));
        desc.dictionary.insert(record);
        let mut var = Object::var(
            0x2001,
            SubObject::new("Live", DataType::Unsigned32, AccessType::Rw),
        );
        var.flags = Some(ObjFlags::from_bits(0));
        desc.dictionary.insert(var);
        let md = write(&desc);
        assert!(md.contains("| 0x2000 | 00 | Count |  | UNSIGNED8 | ro, ObjFlags 0x1 (refuse write on download) |"), "{md}");
        assert!(md.contains("| 0x2000 | 01 | Gain |  | UNSIGNED32 | rw, ObjFlags 0x3 (refuse write on download, refuse read on scan) |"), "{md}");
        assert!(
            md.contains("| 0x2001 |  | Live | VAR | UNSIGNED32 | rw |"),
            "{md}"
        );
    }
}
