//! The EtherCAT commands: `slaves` and `states` (the chain, read only) and `sdos` (a slave's
//! object dictionary by SDO Information).

use std::io::Write;

use crate::ethercat::{EthercatSession, InfoObject};
use crate::ToolError;

/// `sdos`' arguments.
#[derive(Debug, clap::Args)]
pub struct SdosArgs {
    /// The slave's position (1 = first).
    pub node: Option<u8>,
}

/// `slaves` (with `identity`) and `states` on the chain of `interface`, its frames written to
/// `capture` where there is one.
pub fn chain(
    interface: &str,
    identity: bool,
    capture: Option<&crate::link::Capture>,
    desc: Option<&od::DeviceDescription>,
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let io = ToolError::Output;
    let slaves = crate::ethercat::slaves(interface, identity, capture)?;
    let name = |product: u32| {
        desc.filter(|d| d.identity.product_code == product)
            .map(|d| d.identity.order_code.clone())
            .filter(|n| !n.is_empty())
    };
    if json {
        let list: Vec<serde_json::Value> = slaves
            .iter()
            .map(|s| {
                let mut v = serde_json::json!({
                    "position": s.position,
                    "state": crate::ethercat::state_name(s.al_status),
                    "al_status": s.al_status,
                    "al_status_code": s.al_code,
                });
                if let Some([vendor, product, revision, serial]) = s.identity {
                    v["vendor"] = vendor.into();
                    v["product"] = product.into();
                    v["revision"] = revision.into();
                    v["serial"] = serial.into();
                    v["name"] = name(product).into();
                }
                v
            })
            .collect();
        writeln!(out, "{}", serde_json::json!({ "slaves": list })).map_err(io)?;
        return Ok(());
    }
    for s in &slaves {
        let state = crate::ethercat::state_name(s.al_status);
        let mut line = format!("{:>3}  {state:<10}", s.position);
        if identity {
            match s.identity {
                Some([vendor, product, revision, serial]) => line.push_str(&format!(
                    "  0x{vendor:08X}  0x{product:08X}  0x{revision:08X}  {serial:>10}  {}",
                    name(product).unwrap_or_default()
                )),
                None => line.push_str("  (no SII identity)"),
            }
        } else {
            line.push_str(&format!("  AL status code 0x{:04X}", s.al_code));
        }
        writeln!(out, "{}", line.trim_end()).map_err(io)?;
    }
    Ok(())
}

/// `sdos`: the dictionary of the slave at `node` (every slave when `None`) by SDO Information.
pub fn sdos(
    session: &mut EthercatSession,
    args: &SdosArgs,
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    use crate::SdoAccess;
    let positions: Vec<u8> = match args.node {
        Some(n) => {
            session.check_node(n)?;
            vec![n]
        }
        None => (1..=session.slave_count())
            .map(|n| u8::try_from(n).unwrap_or(u8::MAX))
            .collect(),
    };
    for &position in &positions {
        let objects = session.sdos(position)?;
        if json {
            let list: Vec<serde_json::Value> = objects.iter().map(object_json).collect();
            writeln!(
                out,
                "{}",
                serde_json::json!({"position": position, "objects": list})
            )
            .map_err(ToolError::Output)?;
            continue;
        }
        if positions.len() > 1 {
            writeln!(out, "=== Slave {position} ===").map_err(ToolError::Output)?;
        }
        write_objects(&objects, out)?;
    }
    Ok(())
}

/// A data type's name, or its code.
fn type_name(code: u16) -> String {
    match od::coe::info::data_type(code) {
        Some(t) => t.to_string(),
        None => format!("type 0x{code:04X}"),
    }
}

/// An object code's name.
fn object_code(code: u8) -> String {
    match code {
        7 => "VAR".to_string(),
        8 => "ARRAY".to_string(),
        9 => "RECORD".to_string(),
        c => format!("object code {c}"),
    }
}

/// An object and its entries as `sdos --json` gives them.
fn object_json(o: &InfoObject) -> serde_json::Value {
    let entries: Vec<serde_json::Value> = o
        .entries
        .iter()
        .map(|e| {
            serde_json::json!({
                "sub": e.sub, "name": e.name,
                "type": type_name(e.data_type), "type_code": e.data_type,
                "bits": e.bit_length, "access": e.access_text(),
                "rxpdo": e.access & 0x40 != 0, "txpdo": e.access & 0x80 != 0,
            })
        })
        .collect();
    serde_json::json!({
        "index": o.object.index, "object": format!("0x{:04X}", o.object.index),
        "name": o.object.name, "object_code": object_code(o.object.object_code),
        "max_sub": o.object.max_sub, "entries": entries,
    })
}

/// The objects in the layout of IgH's `ethercat sdos`: each object, then each of its entries.
fn write_objects(objects: &[InfoObject], out: &mut dyn Write) -> Result<(), ToolError> {
    let io = ToolError::Output;
    for o in objects {
        writeln!(
            out,
            "SDO 0x{:04X}, {}, \"{}\"",
            o.object.index,
            object_code(o.object.object_code),
            o.object.name
        )
        .map_err(io)?;
        for e in &o.entries {
            writeln!(
                out,
                "  0x{:04X}:{:02X}, {}, {}, {} bit, \"{}\"",
                e.index,
                e.sub,
                e.access_text(),
                type_name(e.data_type),
                e.bit_length,
                e.name
            )
            .map_err(io)?;
        }
    }
    Ok(())
}
