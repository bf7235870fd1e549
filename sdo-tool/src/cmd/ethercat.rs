//! The EtherCAT commands: `slaves` and `states` (the chain, read only) and `sdos` (a slave's
//! object dictionary by SDO Information); [`super::sii`], [`super::reg`] and [`super::pdos`] have
//! the other commands of IgH's tool.

use std::io::Write;

use crate::ethercat::{state_name, Chain, EthercatSession, InfoObject};
use crate::igh::{self, EscInfo, SlaveLine};
use crate::link::Capture;
use crate::ToolError;

/// `sdos`' arguments.
#[derive(Debug, clap::Args)]
pub struct SdosArgs {
    /// The slave's position (1 = first).
    pub node: Option<u8>,
}

/// `slaves`' arguments.
#[derive(Debug, clap::Args)]
pub struct SlavesArgs {
    /// Each slave in detail, as IgH's `ethercat slaves --verbose` shows it: identity, DL
    /// information and ports, mailboxes, the General category of its SII.
    #[arg(long, short)]
    pub verbose: bool,
}

/// One slave as `slaves` read it.
struct Slave {
    line: SlaveLine,
    al_status: u16,
    al_code: u16,
    /// The SII as read (empty when it could not be read).
    sii: Vec<u8>,
    image: Option<od::sii::Image>,
}

/// Reads the slave at `position` for `slaves`: AL status and code, its SII (a slave whose SII cannot
/// be read gets IgH's error flag), and the name: the SII's, else the --od description's where its
/// product code is the slave's, else vendor and product code.
fn read_slave(
    chain: &mut Chain,
    position: u16,
    desc: Option<&od::DeviceDescription>,
) -> Result<Slave, ToolError> {
    let al = chain.read(position, 0x0130, 6)?;
    let al_status = u16::from_le_bytes([al[0], al[1]]);
    let sii = chain.sii(position).map(|r| r.bytes);
    let error = sii.is_err();
    let sii = sii.unwrap_or_default();
    let image = od::sii::Image::read(&sii).ok();
    let [vendor, product, ..] = image.as_ref().map_or([0; 4], |i| i.identity);
    let sii_name = image
        .as_ref()
        .and_then(|i| Some(i.string(i.general()?.name).to_string()))
        .filter(|n| !n.is_empty());
    let od_name = || {
        desc.filter(|d| d.identity.product_code == product)
            .map(|d| d.identity.product_name.clone())
            .filter(|n| !n.is_empty())
    };
    let name = sii_name
        .or_else(od_name)
        .unwrap_or_else(|| igh::identity_name(vendor, product));
    Ok(Slave {
        line: SlaveLine {
            position,
            alias: image.as_ref().map_or(0, od::sii::Image::alias),
            state: state_name(al_status),
            error,
            name,
        },
        al_status,
        al_code: u16::from_le_bytes([al[4], al[5]]),
        sii,
        image,
    })
}

/// What `slaves --verbose` shows of each ESC: port descriptor and features (0x0007–0x0009), DL
/// status (0x0110), whether the system time (0x0910) answers, and the topology.
fn read_escs(chain: &mut Chain) -> Result<Vec<EscInfo>, ToolError> {
    let mut escs = Vec::new();
    for position in 1..=chain.count() {
        let info = chain.read(position, 0x0007, 3)?;
        let dl = chain.read(position, 0x0110, 2)?;
        let features = u16::from_le_bytes([info[1], info[2]]);
        let dc_system_time = features & 0x04 != 0
            && chain
                .read(position, 0x0910, if features & 0x08 != 0 { 8 } else { 4 })
                .is_ok();
        escs.push(EscInfo {
            ports: info[0],
            features,
            dc_system_time,
            dl_status: u16::from_le_bytes([dl[0], dl[1]]),
            next: [None; 4],
        });
    }
    let dl: Vec<u16> = escs.iter().map(|e| e.dl_status).collect();
    for (esc, next) in escs.iter_mut().zip(igh::next_slaves(&dl)) {
        esc.next = next;
    }
    Ok(escs)
}

/// `slaves` on the chain of `interface`, read only: IgH's one-line layout (position, alias and
/// position after it, state, error flag, the SII's name), or with `--verbose` IgH's block per
/// slave. Its frames go to `capture` too, where there is one (as for every command below).
pub fn slaves(
    interface: &str,
    args: &SlavesArgs,
    ctx: super::Context<'_>,
    timeout: std::time::Duration,
    capture: Option<&Capture>,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let io = ToolError::Output;
    let mut chain = Chain::open(interface, timeout, capture)?;
    let mut slaves = Vec::new();
    for position in 1..=chain.count() {
        slaves.push(read_slave(&mut chain, position, ctx.desc)?);
    }
    if ctx.json {
        let list: Vec<serde_json::Value> = slaves.iter().map(slave_json).collect();
        writeln!(out, "{}", serde_json::json!({ "slaves": list })).map_err(io)?;
        return Ok(());
    }
    if !args.verbose {
        let lines: Vec<SlaveLine> = slaves.into_iter().map(|s| s.line).collect();
        return write!(out, "{}", igh::slaves_list(&lines)).map_err(io);
    }
    let escs = read_escs(&mut chain)?;
    for (s, esc) in slaves.iter().zip(&escs) {
        write!(out, "{}", igh::slaves_verbose(&s.line, &s.sii, esc)).map_err(io)?;
    }
    Ok(())
}

/// A slave as `slaves --json` gives it.
fn slave_json(s: &Slave) -> serde_json::Value {
    let mut v = serde_json::json!({
        "position": s.line.position,
        "state": s.line.state,
        "al_status": s.al_status,
        "al_status_code": s.al_code,
        "alias": s.line.alias,
        "name": s.line.name,
        "sii_read": !s.line.error,
    });
    if let Some(i) = &s.image {
        let [vendor, product, revision, serial] = i.identity;
        v["vendor"] = vendor.into();
        v["product"] = product.into();
        v["revision"] = revision.into();
        v["serial"] = serial.into();
        if let Some(g) = i.general() {
            v["order"] = i.string(g.order).into();
            v["group"] = i.string(g.group).into();
        }
    }
    v
}

/// `states` on the chain of `interface`: each slave's AL state and AL status code, read only.
pub fn states(
    interface: &str,
    timeout: std::time::Duration,
    capture: Option<&Capture>,
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let io = ToolError::Output;
    let slaves = crate::ethercat::states(interface, timeout, capture)?;
    if json {
        let list: Vec<serde_json::Value> = slaves
            .iter()
            .map(|s| {
                serde_json::json!({
                    "position": s.position,
                    "state": state_name(s.al_status),
                    "al_status": s.al_status,
                    "al_status_code": s.al_code,
                })
            })
            .collect();
        writeln!(out, "{}", serde_json::json!({ "slaves": list })).map_err(io)?;
        return Ok(());
    }
    for s in &slaves {
        let state = state_name(s.al_status);
        writeln!(
            out,
            "{:>3}  {state:<10}  AL status code 0x{:04X}",
            s.position, s.al_code
        )
        .map_err(io)?;
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
