//! `lss`: the LSS master (CiA 305) on the bus: `scan` (Fastscan until no node without a node-ID
//! answers), `set-id`, `store`, `bitrate`, `inquire`, `switch` and `assign` (every node without a
//! node-ID found, given a node-ID, stored and switched back to waiting). The protocol is
//! `canopen_net::lss`; this module runs it on a bus ([`exchange`]) and speaks to the user.

use std::io::Write;
use std::time::{Duration, Instant};

use canopen_net::lss::{
    AddressPart, LssAddress, LssAnswer, LssError, LssMaster, LssRequest, LssState, PartScan,
};

use super::emit;
use crate::link::{BusEvent, CanBus};
use crate::{Tool, ToolError, UsageError};

/// `lss`'s arguments.
#[derive(Debug, clap::Args)]
pub struct LssArgs {
    /// How long each LSS answer, and each Fastscan step, is waited for, in ms.
    #[arg(long, default_value_t = 100, value_name = "MS")]
    pub lss_timeout_ms: u64,
    /// The service.
    #[command(subcommand)]
    pub command: LssCommand,
}

/// The LSS services of the command line.
#[derive(Debug, clap::Subcommand)]
pub enum LssCommand {
    /// Find every node without a node-ID by Fastscan and print its LSS address
    /// (VENDOR:PRODUCT:REVISION:SERIAL); the nodes are back in the waiting state afterwards.
    Scan,
    /// `set-id ADDRESS NEW_ID` gives the node of that LSS address (VENDOR:PRODUCT:REVISION:SERIAL)
    /// the node-ID; `set-id --fastscan NEW_ID…` gives each of the next nodes without a node-ID
    /// Fastscan finds the next node-ID. The nodes stay in the configuration state (for `lss store`,
    /// `lss inquire`, `lss bitrate`) until `lss switch waiting`.
    SetId {
        /// Find the nodes by Fastscan instead of an address.
        #[arg(long)]
        fastscan: bool,
        /// ADDRESS NEW_ID, or with --fastscan NEW_ID…
        #[arg(required = true, num_args = 1.., value_name = "ADDRESS|NEW_ID")]
        words: Vec<String>,
    },
    /// Store configuration: the node in the configuration state keeps its node-ID and bit timing.
    Store,
    /// Configure bit timing (CiA 301 table): 1000, 800, 500, 250, 125, 100, 50, 20 or 10 kbit/s.
    Bitrate {
        /// The bit rate in kbit/s.
        kbit: u32,
    },
    /// The identity (LSS address) and node-ID of the node in the configuration state.
    Inquire,
    /// Switch state global: every node to `waiting` or `configuration`.
    Switch {
        /// waiting or configuration.
        state: String,
    },
    /// Identify: with no RANGE, whether a node without a node-ID is on the bus (identify
    /// non-configured remote slave); with VENDOR:PRODUCT:REVISIONS:SERIALS (REVISIONS and SERIALS a
    /// number or LOW-HIGH), whether a node of that vendor and product with its revision and serial
    /// number in the ranges is (identify remote slave). Prints yes or no.
    Identify {
        /// VENDOR:PRODUCT:REVISIONS:SERIALS.
        range: Option<String>,
    },
    /// Find every node without a node-ID by Fastscan, give them node-IDs from FIRST_ID on, store
    /// each and switch it back to waiting (where it takes the node-ID at once).
    Assign {
        /// The first node-ID given, 1–127.
        first_id: u8,
    },
}

/// Runs `request` on `bus` to its end: frames sent, answers taken, silence timed on this host's
/// clock.
pub fn exchange(
    bus: &mut dyn CanBus,
    master: &mut LssMaster,
    request: LssRequest,
) -> Result<LssAnswer, ToolError> {
    master.start(Instant::now(), request)?;
    loop {
        while let Some(frame) = master.poll_transmit() {
            bus.send(&frame)?;
        }
        if let Some(outcome) = master.poll_event() {
            return Ok(outcome?);
        }
        let Some(due) = master.poll_timeout() else {
            // No service waits and none finished: nothing more can come.
            return Err(LssError::Timeout {
                service: request.name(),
                timeout: master.timeout(),
            }
            .into());
        };
        let left = due.saturating_duration_since(Instant::now());
        // Another participant's frames do not hold the bound back: the time is checked after each.
        if let Some(BusEvent::Frame {
            frame, received, ..
        }) = bus.recv(left)?
        {
            master.handle_frame(received, &frame);
        }
        master.handle_timeout(Instant::now());
    }
}

/// An LSS address as `VENDOR:PRODUCT:REVISION:SERIAL`, each in hex with `0x`.
pub fn address_text(a: &LssAddress) -> String {
    format!(
        "0x{:08X}:0x{:08X}:0x{:08X}:0x{:08X}",
        a[0], a[1], a[2], a[3]
    )
}

/// `VENDOR:PRODUCT:REVISION:SERIAL`, each decimal or hex with `0x`.
pub fn parse_address(text: &str) -> Result<LssAddress, UsageError> {
    let bad = || UsageError::LssAddress {
        text: text.to_string(),
    };
    let parts: Vec<u32> = text
        .split(':')
        .map(|p| number(p).ok_or_else(bad))
        .collect::<Result<_, _>>()?;
    <LssAddress>::try_from(parts).map_err(|_| bad())
}

/// `VENDOR:PRODUCT:REVISIONS:SERIALS`, REVISIONS and SERIALS a number or `LOW-HIGH`: the request
/// identify remote slave.
fn parse_range(text: &str) -> Result<LssRequest, UsageError> {
    let bad = || UsageError::LssRange {
        text: text.to_string(),
    };
    let parts: Vec<&str> = text.split(':').collect();
    let [vendor, product, revision, serial] = parts[..] else {
        return Err(bad());
    };
    let range = |p: &str| -> Option<(u32, u32)> {
        match p.split_once('-') {
            Some((low, high)) => Some((number(low)?, number(high)?)),
            None => number(p).map(|v| (v, v)),
        }
    };
    Ok(LssRequest::IdentifyRemote {
        vendor: number(vendor).ok_or_else(bad)?,
        product: number(product).ok_or_else(bad)?,
        revision: range(revision).ok_or_else(bad)?,
        serial: range(serial).ok_or_else(bad)?,
    })
}

fn number(text: &str) -> Option<u32> {
    let t = text.trim();
    match t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")) {
        Some(h) => u32::from_str_radix(h, 16).ok(),
        None => t.parse().ok(),
    }
}

fn node_id(text: &str) -> Result<u8, UsageError> {
    number(text)
        .and_then(|n| u8::try_from(n).ok())
        .filter(|n| (1..=127).contains(n))
        .ok_or_else(|| UsageError::LssNodeId {
            text: text.to_string(),
        })
}

/// The CiA 301 bit-timing table index of a bit rate in kbit/s.
pub fn bit_timing_index(kbit: u32) -> Option<u8> {
    [1000, 800, 500, 250, 125, 100, 50, 20, 10]
        .iter()
        .position(|&k| k == kbit)
        .map(|i| i as u8)
}

fn address_json(a: &LssAddress) -> serde_json::Value {
    serde_json::json!({
        "vendor": format!("0x{:08X}", a[0]),
        "product": format!("0x{:08X}", a[1]),
        "revision": format!("0x{:08X}", a[2]),
        "serial": format!("0x{:08X}", a[3]),
    })
}

/// What became of one node `assign` found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Assigned {
    /// Its LSS address.
    pub address: LssAddress,
    /// The node-ID it was given.
    pub node_id: u8,
    /// Why store configuration failed, when it did (the node-ID is the node's until it restarts).
    pub not_stored: Option<LssError>,
}

/// Finds every node without a node-ID by Fastscan and gives them node-IDs from `first` on: each
/// configured, stored when `store`, and switched back to waiting (where it takes its node-ID and
/// no longer answers Fastscan); `parts` says how the Fastscan takes each part of the address.
/// `each` hears of every node as it is done.
pub fn assign(
    bus: &mut dyn CanBus,
    master: &mut LssMaster,
    (first, store): (u8, bool),
    parts: [PartScan; 4],
    mut each: impl FnMut(&Assigned) -> Result<(), ToolError>,
) -> Result<usize, ToolError> {
    exchange(bus, master, LssRequest::SwitchGlobal(LssState::Waiting))?;
    let mut count = 0;
    loop {
        let found = exchange(bus, master, LssRequest::FastscanWith(parts))?;
        let LssAnswer::Found(address) = found else {
            return Ok(count);
        };
        let node_id = first
            .checked_add(count as u8)
            .filter(|n| *n <= 127)
            .ok_or(UsageError::LssNodeIdsUsedUp { first })?;
        exchange(bus, master, LssRequest::ConfigureNodeId(node_id))?;
        let not_stored = match store {
            true => match exchange(bus, master, LssRequest::Store) {
                Ok(_) => None,
                Err(ToolError::Lss(e @ LssError::Refused { .. })) => Some(e),
                Err(e) => return Err(e),
            },
            false => None,
        };
        exchange(bus, master, LssRequest::SwitchGlobal(LssState::Waiting))?;
        count += 1;
        each(&Assigned {
            address,
            node_id,
            not_stored,
        })?;
    }
}

/// `lss` on `tool`'s bus.
pub fn run(
    args: &LssArgs,
    tool: &mut Tool,
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let mut master = LssMaster::with_timeout(Duration::from_millis(args.lss_timeout_ms.max(1)));
    let bus = tool.bus.as_mut();
    let ok = |out: &mut dyn Write| emit(out, json, "OK", serde_json::json!({"ok": true}));
    match &args.command {
        LssCommand::Scan => {
            exchange(
                bus,
                &mut master,
                LssRequest::SwitchGlobal(LssState::Waiting),
            )?;
            let mut found = 0;
            while let LssAnswer::Found(a) = exchange(bus, &mut master, LssRequest::Fastscan)? {
                found += 1;
                emit(out, json, address_text(&a), address_json(&a))?;
            }
            exchange(
                bus,
                &mut master,
                LssRequest::SwitchGlobal(LssState::Waiting),
            )?;
            if found == 0 && !json {
                writeln!(out, "no node without a node-ID answered").map_err(ToolError::Output)?;
            }
            Ok(())
        }
        LssCommand::SetId { fastscan, words } => {
            set_id(bus, &mut master, *fastscan, words, json, out)
        }
        LssCommand::Store => {
            exchange(bus, &mut master, LssRequest::Store)?;
            ok(out)
        }
        LssCommand::Bitrate { kbit } => {
            let index = bit_timing_index(*kbit).ok_or(UsageError::LssBitRate { kbit: *kbit })?;
            let request = LssRequest::ConfigureBitTiming { table: 0, index };
            exchange(bus, &mut master, request)?;
            ok(out)
        }
        LssCommand::Inquire => {
            let mut address = [0u32; 4];
            for part in AddressPart::ALL {
                if let LssAnswer::Value(v) = exchange(bus, &mut master, LssRequest::Inquire(part))?
                {
                    address[usize::from(part.index())] = v;
                }
            }
            let id = match exchange(bus, &mut master, LssRequest::InquireNodeId)? {
                LssAnswer::NodeId(id) => id,
                _ => 0xFF,
            };
            let id_text = if id == 0xFF {
                "none".to_string()
            } else {
                id.to_string()
            };
            let mut value = address_json(&address);
            value["node_id"] = if id == 0xFF {
                serde_json::Value::Null
            } else {
                id.into()
            };
            let text = format!("{} node-ID {id_text}", address_text(&address));
            emit(out, json, text, value)
        }
        LssCommand::Identify { range } => {
            let request = match range {
                None => LssRequest::IdentifyNonConfigured,
                Some(text) => parse_range(text)?,
            };
            let answered = matches!(
                exchange(bus, &mut master, request)?,
                LssAnswer::Identified(true)
            );
            let what = match range {
                None => "a node without a node-ID".to_string(),
                Some(text) => format!("a node of {text}"),
            };
            let text = if answered {
                format!("yes: {what} answered")
            } else {
                format!("no: {what} did not answer")
            };
            emit(out, json, text, serde_json::json!({"answered": answered}))
        }
        LssCommand::Switch { state } => {
            let state = match state.as_str() {
                "waiting" => LssState::Waiting,
                "configuration" => LssState::Configuration,
                _ => {
                    return Err(UsageError::LssState {
                        text: state.clone(),
                    }
                    .into())
                }
            };
            exchange(bus, &mut master, LssRequest::SwitchGlobal(state))?;
            ok(out)
        }
        LssCommand::Assign { first_id } => {
            if !(1..=127).contains(first_id) {
                return Err(UsageError::LssNodeId {
                    text: first_id.to_string(),
                }
                .into());
            }
            let all = [PartScan::Scan; 4];
            let count = assign(bus, &mut master, (*first_id, true), all, |a| {
                let mut value = address_json(&a.address);
                value["node_id"] = a.node_id.into();
                value["stored"] = a.not_stored.is_none().into();
                let stored = match &a.not_stored {
                    None => "stored".to_string(),
                    Some(e) => format!("not stored: {e}"),
                };
                let text = format!(
                    "{} node-ID {} {stored}",
                    address_text(&a.address),
                    a.node_id
                );
                emit(out, json, text, value)
            })?;
            if count == 0 && !json {
                writeln!(out, "no node without a node-ID answered").map_err(ToolError::Output)?;
            }
            Ok(())
        }
    }
}

/// `set-id ADDRESS NEW_ID` or `set-id --fastscan NEW_ID…`.
fn set_id(
    bus: &mut dyn CanBus,
    master: &mut LssMaster,
    fastscan: bool,
    words: &[String],
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let (address, ids) = match (fastscan, words) {
        (true, ids) => (None, ids),
        (false, [address, id]) => (Some(parse_address(address)?), std::slice::from_ref(id)),
        (false, _) => return Err(UsageError::LssSetId.into()),
    };
    let ids: Vec<u8> = ids.iter().map(|t| node_id(t)).collect::<Result<_, _>>()?;
    if fastscan {
        exchange(bus, master, LssRequest::SwitchGlobal(LssState::Waiting))?;
    }
    for id in ids {
        let address = match address {
            Some(a) => {
                exchange(bus, master, LssRequest::SwitchSelective(a))?;
                a
            }
            None => match exchange(bus, master, LssRequest::Fastscan)? {
                LssAnswer::Found(a) => a,
                _ => return Err(ToolError::LssNotFound),
            },
        };
        exchange(bus, master, LssRequest::ConfigureNodeId(id))?;
        let mut value = address_json(&address);
        value["node_id"] = id.into();
        emit(
            out,
            json,
            format!("{} node-ID {id}", address_text(&address)),
            value,
        )?;
    }
    Ok(())
}
