//! The gateway's LSS requests (CiA 309-3 §7.5 and CANopenNode's): `lss_switch_glob 0|1`,
//! `lss_switch_sel VENDOR PRODUCT REVISION SERIAL`, `lss_set_node N`, `lss_conf_bitrate TABLE
//! INDEX`, `lss_activate_bitrate DELAY_MS`, `lss_store`, `lss_inquire_addr [PART]` (0–3, or the
//! command specifier 0x5A–0x5D), `lss_get_node`, `_lss_fastscan [TIMEOUT_MS]` and `lss_allnodes
//! [TIMEOUT_MS [FIRST_ID STORE [TYPE VENDOR TYPE PRODUCT TYPE REVISION TYPE SERIAL]]]` (TYPE 0
//! scan the part, 1 skip it, 2 match the value given).
//!
//! Replies: `OK`; an address part as `0x%08X` (four of them, space-separated, for the whole
//! address); a node-ID in decimal; `lss_allnodes` a comment line `# Node-ID N assigned to: …` per
//! node and `# Found N nodes, search finished.` before its `OK`. A slave's refusal is `ERROR:102`,
//! silence `ERROR:103` (Fastscan: no node without a node-ID answered). A TIMEOUT_MS is 1 to 10000.

use std::time::Duration;

use canopen_net::lss::{
    AddressPart, LssAnswer, LssError, LssMaster, LssRequest, LssState, PartScan, DEFAULT_TIMEOUT,
};

use super::{gateway_error, number, Gateway};
use crate::cmd::lss::{assign, exchange};
use crate::ToolError;

/// Whether `cmd` is one of the LSS requests.
pub(super) fn is_lss(cmd: &str) -> bool {
    cmd.starts_with("lss_") || cmd == "_lss_fastscan"
}

fn reply(r: Result<String, ToolError>) -> String {
    match r {
        Ok(v) => v,
        Err(ToolError::Lss(LssError::Refused { .. } | LssError::NodeId { .. })) => {
            gateway_error(102)
        }
        Err(ToolError::Lss(_) | ToolError::LssNotFound) => gateway_error(103),
        Err(ToolError::Usage(_)) => gateway_error(101),
        Err(_) => gateway_error(102),
    }
}

fn timeout(arg: Option<&&str>) -> Option<Duration> {
    match arg {
        None => Some(DEFAULT_TIMEOUT),
        Some(t) => number(t)
            .filter(|ms| (1..=10_000).contains(ms))
            .map(|ms| Duration::from_millis(u64::from(ms))),
    }
}

impl Gateway {
    /// One LSS request: the reply.
    pub(super) fn lss(&mut self, cmd: &str, args: &[&str]) -> String {
        let nums: Option<Vec<u32>> = args.iter().map(|a| number(a)).collect();
        let Some(nums) = nums else {
            return gateway_error(101);
        };
        let request = match (cmd, nums.as_slice()) {
            ("lss_switch_glob", [mode @ (0 | 1)]) => LssRequest::SwitchGlobal(if *mode == 0 {
                LssState::Waiting
            } else {
                LssState::Configuration
            }),
            ("lss_switch_sel", [v, p, r, s]) => LssRequest::SwitchSelective([*v, *p, *r, *s]),
            ("lss_set_node", [id]) => match u8::try_from(*id) {
                Ok(id @ (1..=127 | 0xFF)) => LssRequest::ConfigureNodeId(id),
                _ => return gateway_error(101),
            },
            ("lss_conf_bitrate", [table, index]) => {
                match (u8::try_from(*table), u8::try_from(*index)) {
                    (Ok(table), Ok(index)) => LssRequest::ConfigureBitTiming { table, index },
                    _ => return gateway_error(101),
                }
            }
            ("lss_activate_bitrate", [delay]) => match u16::try_from(*delay) {
                Ok(delay_ms) => LssRequest::ActivateBitTiming { delay_ms },
                Err(_) => return gateway_error(101),
            },
            ("lss_store", []) => LssRequest::Store,
            ("lss_inquire_addr", []) => return self.inquire_address(),
            ("lss_inquire_addr", [part]) => {
                let part = match *part {
                    p @ 0..=3 => p,
                    p @ 0x5A..=0x5D => p - 0x5A,
                    _ => return gateway_error(101),
                };
                LssRequest::Inquire(AddressPart::ALL[part as usize])
            }
            ("lss_get_node", []) => LssRequest::InquireNodeId,
            ("_lss_fastscan", [] | [_]) => {
                let Some(t) = timeout(args.first()) else {
                    return gateway_error(101);
                };
                return self.fastscan(t);
            }
            ("lss_allnodes", [] | [_] | [_, _, _] | [_, _, _, _, _, _, _, _, _, _, _]) => {
                let Some(t) = timeout(args.first()) else {
                    return gateway_error(101);
                };
                let (first, store) = match nums.get(1..3) {
                    Some(&[first, store]) => (first, store),
                    _ => (2, 1),
                };
                let (Ok(first @ 1..=127), store @ (0 | 1)) = (u8::try_from(first), store) else {
                    return gateway_error(101);
                };
                let Some(parts) = scan_parts(nums.get(3..).unwrap_or_default()) else {
                    return gateway_error(101);
                };
                return self.all_nodes(t, first, store == 1, parts);
            }
            _ => return gateway_error(101),
        };
        let mut master = LssMaster::new();
        reply(
            exchange(self.tool.bus.as_mut(), &mut master, request).map(|a| match a {
                LssAnswer::Value(v) => format!("0x{v:08X}"),
                LssAnswer::NodeId(id) => id.to_string(),
                _ => "OK".to_string(),
            }),
        )
    }

    fn inquire_address(&mut self) -> String {
        let mut master = LssMaster::new();
        let mut parts = Vec::new();
        for part in AddressPart::ALL {
            match exchange(
                self.tool.bus.as_mut(),
                &mut master,
                LssRequest::Inquire(part),
            ) {
                Ok(LssAnswer::Value(v)) => parts.push(format!("0x{v:08X}")),
                Ok(_) => return gateway_error(102),
                Err(e) => return reply(Err(e)),
            }
        }
        parts.join(" ")
    }

    fn fastscan(&mut self, timeout: Duration) -> String {
        let mut master = LssMaster::with_timeout(timeout);
        let bus = self.tool.bus.as_mut();
        let found = exchange(
            bus,
            &mut master,
            LssRequest::SwitchGlobal(LssState::Waiting),
        )
        .and_then(|_| exchange(bus, &mut master, LssRequest::Fastscan));
        match found {
            Ok(LssAnswer::Found(a)) => {
                format!(
                    "0x{:08X} 0x{:08X} 0x{:08X} 0x{:08X}",
                    a[0], a[1], a[2], a[3]
                )
            }
            Ok(_) => gateway_error(103),
            Err(e) => reply(Err(e)),
        }
    }

    fn all_nodes(
        &mut self,
        timeout: Duration,
        first: u8,
        store: bool,
        parts: [PartScan; 4],
    ) -> String {
        let mut master = LssMaster::with_timeout(timeout);
        let mut lines = String::new();
        let bus = self.tool.bus.as_mut();
        let count = assign(bus, &mut master, (first, store), parts, |n| {
            let a = n.address;
            lines.push_str(&format!(
                "# Node-ID {} assigned to: 0x{:08X} 0x{:08X} 0x{:08X} 0x{:08X}\n",
                n.node_id, a[0], a[1], a[2], a[3]
            ));
            Ok(())
        });
        match count {
            Ok(n) => format!(
                "{lines}# Found {n} node{}, search finished.\nOK",
                if n == 1 { "" } else { "s" }
            ),
            Err(e) => format!("{lines}{}", reply(Err(e))),
        }
    }
}

/// `lss_allnodes`' scan of the four parts: none given, each scanned; else four pairs `TYPE VALUE`,
/// TYPE 0 scan, 1 skip, 2 match VALUE (CANopenNode's gateway).
fn scan_parts(pairs: &[u32]) -> Option<[PartScan; 4]> {
    if pairs.is_empty() {
        return Some([PartScan::Scan; 4]);
    }
    let mut parts = [PartScan::Scan; 4];
    for (part, pair) in parts.iter_mut().zip(pairs.chunks(2)) {
        *part = match pair {
            [0, _] => PartScan::Scan,
            [1, _] => PartScan::Skip,
            [2, v] => PartScan::Match(*v),
            _ => return None,
        };
    }
    Some(parts)
}
