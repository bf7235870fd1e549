//! What `ethercat-node --list` prints: every device of an ESI file, one tab-separated row each,
//! with the drive axes the emulator runs behind it and what a master needs to move them in csp, so
//! that a script (the acceptance runner) can run each device without reading the ESI itself.
//!
//! The columns ([`HEADER`]):
//!
//! - `device`: the device's name in messages (its type name, else its name);
//! - `select`: what `--device` takes to choose it (its product code where no other device of the
//!   file has that code, else its type name);
//! - `name`: the name a master reads from its SII as the slave's name (SOEM: the type name; the
//!   first 40 characters);
//! - `vendor`, `product`, `revision`: its identity, `0x` and eight hex digits;
//! - `axes`: the drive axes joined by `+`: `0+1` for CiA 402 axes (objects at 0x6000 + 0x800·axis),
//!   `m0+m1` for MDP 742 channels ([`crate::generic::mdp`]), `-` for none;
//! - `csp`: `yes` where the ESI's 0x6502 (supported drive modes) of an axis has bit 7 (csp), `no`
//!   where the ESI gives 0x6502 values without it, `-` where it gives none (or the axes are MDP 742
//!   channels, which have no 0x6502);
//! - `rx`, `tx`: the RxPDOs and TxPDOs a master assigns (0x1C12, 0x1C13) so that the process data
//!   carries each axis's controlword and target position, statusword and position actual: `=` when
//!   the power-on assignment does, else the mapping objects joined by `,` (`0x1600,0x1606`), `-`
//!   when there is no such assignment (the note says why) or no axis;
//! - `note`: why the device has no axis though it has a controlword (another layout of the drive
//!   profile), why it cannot be emulated, or why no assignment carries what csp needs; `-` else.
//!
//! Each device of several revisions is listed once, at its newest (the one `--device` chooses).

use std::path::Path;

use od::dict::{Address, Dictionary};
use od::load::Format;

use crate::generic::mdp::Channels;
use crate::generic::{device_name, parse_number, Template};
use crate::node_cli::CliError;

/// The header row.
pub const HEADER: &str = "device\tselect\tname\tvendor\tproduct\trevision\taxes\tcsp\trx\ttx\tnote";

/// One device of a file. See the [module documentation](self).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Listed {
    /// The name in messages.
    pub device: String,
    /// What `--device` takes.
    pub select: String,
    /// The SII name.
    pub name: String,
    /// Vendor ID.
    pub vendor: u32,
    /// Product code.
    pub product: u32,
    /// Revision.
    pub revision: u32,
    /// The axes: CiA 402 axes, or MDP 742 channels.
    pub axes: Vec<u8>,
    /// Whether the axes are MDP 742 channels.
    pub channels: bool,
    /// Whether the ESI's 0x6502 claims csp (`None`: it gives no value).
    pub csp: Option<bool>,
    /// The RxPDOs and TxPDOs to assign for csp (`None`: the power-on assignment does).
    pub assignment: (Option<Vec<u16>>, Option<Vec<u16>>),
    /// What stands in the way, if anything.
    pub note: Option<String>,
}

impl Listed {
    /// The row, tab-separated.
    pub fn row(&self) -> String {
        let clean = |s: &str| s.replace(['\t', '\n', '\r'], " ");
        let axes = if self.axes.is_empty() {
            "-".to_string()
        } else {
            let prefix = if self.channels { "m" } else { "" };
            self.axes
                .iter()
                .map(|a| format!("{prefix}{a}"))
                .collect::<Vec<_>>()
                .join("+")
        };
        let csp = match self.csp {
            Some(true) => "yes",
            Some(false) => "no",
            None => "-",
        };
        let pdos = |p: &Option<Vec<u16>>| match p {
            _ if self.axes.is_empty() || self.note.is_some() => "-".to_string(),
            None => "=".to_string(),
            Some(list) => list
                .iter()
                .map(|i| format!("{i:#06X}"))
                .collect::<Vec<_>>()
                .join(","),
        };
        [
            clean(&self.device),
            clean(&self.select),
            clean(&self.name),
            format!("{:#010X}", self.vendor),
            format!("{:#010X}", self.product),
            format!("{:#010X}", self.revision),
            axes,
            csp.to_string(),
            pdos(&self.assignment.0),
            pdos(&self.assignment.1),
            self.note.as_deref().map_or_else(|| "-".to_string(), clean),
        ]
        .join("\t")
    }
}

/// The devices of the ESI file at `path`, in the file's order (see the [module
/// documentation](self)).
pub fn list(path: &Path) -> Result<Vec<Listed>, CliError> {
    let limit = od::load::limit_from(
        od::load::MAX_FILE_BYTES,
        std::env::var_os(od::load::LIMIT_VARIABLE).as_deref(),
    )
    .map_err(|e| CliError::Load(e.to_string()))?;
    let bytes = od::load::read_limited(path, limit).map_err(|e| CliError::Load(e.to_string()))?;
    if Format::detect(path, &bytes) != Some(Format::Esi) {
        return Err(CliError::Esi {
            path: path.display().to_string(),
            why: "not an ESI (EtherCATInfo) file".into(),
        });
    }
    let name = path.display().to_string();
    let devices = od::esi::read_all(&bytes, &name).map_err(|e| CliError::Load(e.to_string()))?;
    // Each device once, at its newest revision.
    let mut newest: Vec<&od::device::DeviceDescription> = Vec::new();
    for d in &devices {
        let same = |o: &&od::device::DeviceDescription| {
            o.identity.product_code == d.identity.product_code
                && o.identity
                    .order_code
                    .eq_ignore_ascii_case(&d.identity.order_code)
        };
        match newest.iter().position(same) {
            Some(k) if newest[k].identity.revision < d.identity.revision => newest[k] = d,
            Some(_) => {}
            None => newest.push(d),
        }
    }
    Ok(newest.iter().map(|d| listed(d, &newest)).collect())
}

/// One device, made ready as `ethercat-node` makes it.
fn listed(desc: &od::device::DeviceDescription, all: &[&od::device::DeviceDescription]) -> Listed {
    let id = &desc.identity;
    let device = device_name(desc);
    let code_shared = all
        .iter()
        .filter(|o| o.identity.product_code == id.product_code)
        .count()
        > 1;
    let select = if code_shared {
        device.clone()
    } else {
        format!("{:#010x}", id.product_code)
    };
    debug_assert!(code_shared || parse_number(&select) == Some(id.product_code));
    let mut out = Listed {
        name: device.clone(),
        device,
        select: select.clone(),
        vendor: id.vendor_id,
        product: id.product_code,
        revision: id.revision,
        axes: Vec::new(),
        channels: false,
        csp: None,
        assignment: (None, None),
        note: None,
    };
    // A device without slots whose dictionary has no drive axis and nothing of a drive is none.
    let slots = desc.ethercat.as_ref().is_some_and(|ec| ec.slots.is_some());
    let none = ds402::drive::Drive::axes(&desc.dictionary).is_empty()
        && Channels::of(&desc.dictionary).is_none()
        && drive_like(desc).is_none();
    if !slots && none {
        return out;
    }
    // As `ethercat-node --device` makes it (the device of the newest revision, its modules the
    // slots' defaults).
    let template = match Template::new(desc.clone(), None) {
        Ok(t) => t,
        Err(e) => {
            if let Some(drive) = drive_like(desc) {
                out.note = Some(format!(
                    "{drive}, but ethercat-node cannot run the device: {e}"
                ));
            }
            return out;
        }
    };
    out.axes = template.axes();
    out.channels = template.channels().is_some();
    if out.axes.is_empty() {
        out.note = drive_like(template.description()).map(|d| {
            format!(
                "{d}, but no CiA 402 axis (0x6040 and 0x6041 UNSIGNED16 at sub-index 0, at \
                 0x6000 + 0x800·axis) and no MDP 742 channel (0x7010:01 and 0x6010:01 \
                 UNSIGNED16 and a target, at + 0x100·channel)"
            )
        });
        return out;
    }
    if !out.channels {
        let claims: Vec<bool> = out
            .axes
            .iter()
            .filter_map(|&a| {
                let e = desc
                    .dictionary
                    .entry(0x6502 + 0x800 * u16::from(a), 0)
                    .ok()?;
                if !e.has_value() {
                    return None;
                }
                let v = e.current()?.as_i128()?;
                Some(v & 1 << 7 != 0)
            })
            .collect();
        if !claims.is_empty() {
            out.csp = Some(claims.contains(&true));
        }
    }
    let (outputs, inputs) = csp_entries(&out.axes, template.channels());
    let dict = &template.description().dictionary;
    let pdos = template.pdos();
    match (
        pdos.assignment_for(dict, false, &outputs),
        pdos.assignment_for(dict, true, &inputs),
    ) {
        (Ok(rx), Ok(tx)) => out.assignment = (rx, tx),
        (Err(why), _) | (_, Err(why)) => out.note = Some(why),
    }
    out
}

/// The entries csp needs in the outputs (controlword, target position) and the inputs
/// (statusword, position actual) of `axes`.
fn csp_entries(axes: &[u8], channels: Option<&Channels>) -> (Vec<Address>, Vec<Address>) {
    let mut outputs = Vec::new();
    let mut inputs = Vec::new();
    for &a in axes {
        if channels.is_some() {
            let off = crate::generic::mdp::CHANNEL_STRIDE * u16::from(a);
            outputs.extend([Address::new(0x7010 + off, 1), Address::new(0x7010 + off, 5)]);
            inputs.extend([
                Address::new(0x6010 + off, 1),
                Address::new(0x6000 + off, 0x11),
            ]);
        } else {
            let base = 0x6000 + 0x800 * u16::from(a);
            outputs.extend([Address::new(base + 0x40, 0), Address::new(base + 0x7A, 0)]);
            inputs.extend([Address::new(base + 0x41, 0), Address::new(base + 0x64, 0)]);
        }
    }
    (outputs, inputs)
}

/// What makes the device look like a drive though no axis was found, as a note says it: a
/// controlword among the CiA 402 objects of an axis (0x6040 + 0x800·axis, UNSIGNED16 at any
/// sub-index), or PDO entries (of the device or its modules) named a controlword and a mode of
/// operation (a drive's process data in another layout). `None` for a device that is no drive (an
/// I/O module's "control word" has no mode of operation beside it).
fn drive_like(desc: &od::device::DeviceDescription) -> Option<String> {
    let dict: &Dictionary = &desc.dictionary;
    for axis in 0..8u16 {
        let index = 0x6040 + 0x800 * axis;
        if let Some(o) = dict.object(index) {
            if let Some((sub, s)) = o
                .subs
                .iter()
                .find(|(_, s)| s.data_type == od::types::DataType::Unsigned16)
            {
                return Some(format!(
                    "the controlword of CiA 402 axis {axis} at {index:#06X}:{sub:02X} ({:?})",
                    s.name.trim()
                ));
            }
        }
    }
    let ec = desc.ethercat.as_ref()?;
    let pdos = ec.rx_pdos.iter().chain(&ec.tx_pdos).chain(
        ec.modules
            .iter()
            .flat_map(|m| m.rx_pdos.iter().chain(&m.tx_pdos)),
    );
    let entries: Vec<&od::device::PdoEntry> = pdos.flat_map(|p| p.entries.iter()).collect();
    let named = |words: &[&str]| {
        entries.iter().find(|e| {
            let name = e.name.to_ascii_lowercase();
            words.iter().any(|w| name.contains(w))
        })
    };
    let control = named(&["controlword", "control word"])?;
    named(&[
        "mode of operation",
        "modes of operation",
        "op mode",
        "opmode",
        "operation mode",
    ])?;
    Some(format!(
        "PDO entries of a drive ({:?} at {:#06X}:{:02X}, a mode of operation)",
        control.name.trim(),
        control.index,
        control.sub
    ))
}
