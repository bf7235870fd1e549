//! A CiA 309-3 ASCII gateway on the tool: one request per line, one reply per request.
//!
//! Requests: `[SEQ] [[NET] NODE] COMMAND …` with COMMAND one of `r[ead] IDX SUB [TYPE]`,
//! `w[rite] IDX SUB TYPE VALUE`, `start`, `stop`, `preop[erational]`, `reset node`,
//! `reset comm[unication]`, `set network N`, `set node N`, `set sdo_timeout MS`, `set sdo_block 0|1`,
//! `help`, and the LSS requests `lss_switch_glob`, `lss_switch_sel`, `lss_set_node`,
//! `lss_conf_bitrate`, `lss_activate_bitrate`, `lss_store`, `lss_inquire_addr`, `lss_get_node`,
//! `_lss_fastscan` and `lss_allnodes`. `#` starts a comment. Replies: `[SEQ] OK`, `[SEQ] VALUE`,
//! `[SEQ] ERROR:0x0602000 #meaning` for an SDO abort, `[SEQ] ERROR:NNN #meaning` for the gateway's own errors (100 request not
//! supported, 101 syntax error, 103 time-out, 105 no default node set, 106 unsupported net, 107
//! unsupported node). The `[SEQ]` of the reply is the request's; a request without one gets a reply
//! without one.

use std::time::Duration;

mod lss;

use crate::{NmtCommand, Tool, ToolError};

/// The gateway: the tool and its defaults.
pub struct Gateway {
    /// The tool the requests run on.
    pub tool: Tool,
    /// The default node (`set node`).
    pub node: Option<u8>,
}

/// The text of `help`.
pub const HELP: &str = "[SEQ] [[NET] NODE] r[ead] IDX SUB [TYPE] | w[rite] IDX SUB TYPE VALUE | start | stop | \
preop | reset node | reset comm | set network N | set node N | set sdo_timeout MS | set sdo_block 0|1 | help | \
lss_switch_glob 0|1 | lss_switch_sel VENDOR PRODUCT REVISION SERIAL | lss_set_node N | \
lss_conf_bitrate TABLE INDEX | lss_activate_bitrate DELAY_MS | lss_store | lss_inquire_addr [0-3] | \
lss_get_node | _lss_fastscan [TIMEOUT_MS] | lss_allnodes [TIMEOUT_MS [FIRST_ID STORE]]";

fn gateway_error(code: u16) -> String {
    let text = match code {
        100 => "Request not supported",
        101 => "Syntax error",
        103 => "Time-out",
        105 => "No default node set",
        106 => "Unsupported net",
        107 => "Unsupported node",
        _ => "Request not processed due to internal state",
    };
    format!("ERROR:{code} #{text}")
}

/// Splits a request into words, keeping a `"quoted string"` as one word.
fn words(text: &str) -> Result<Vec<String>, ()> {
    let mut out = Vec::new();
    let mut chars = text.chars().peekable();
    while let Some(&c) = chars.peek() {
        if c.is_whitespace() {
            chars.next();
            continue;
        }
        let mut w = String::new();
        if c == '"' {
            w.push(chars.next().unwrap_or('"'));
            loop {
                match chars.next() {
                    Some('"') => {
                        w.push('"');
                        break;
                    }
                    Some(ch) => w.push(ch),
                    None => return Err(()),
                }
            }
        } else {
            while let Some(&ch) = chars.peek() {
                if ch.is_whitespace() {
                    break;
                }
                w.push(ch);
                chars.next();
            }
        }
        out.push(w);
    }
    Ok(out)
}

fn number(text: &str) -> Option<u32> {
    let t = text.trim();
    match t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")) {
        Some(h) => u32::from_str_radix(h, 16).ok(),
        None => t.parse().ok(),
    }
}

impl Gateway {
    /// A gateway on `tool` with no default node.
    pub fn new(tool: Tool) -> Gateway {
        Gateway { tool, node: None }
    }

    /// The reply to one request line; `None` for an empty line or a comment.
    pub fn handle(&mut self, line: &str) -> Option<String> {
        let text = line.split('#').next().unwrap_or("").trim();
        if text.is_empty() {
            return None;
        }
        let (seq, rest) = match text.strip_prefix('[') {
            Some(r) => match r.split_once(']') {
                Some((s, rest)) if s.trim().parse::<u32>().is_ok() => {
                    (Some(s.trim().to_string()), rest.trim())
                }
                _ => return Some(gateway_error(101)),
            },
            None => (None, text),
        };
        let reply = self.request(rest);
        // A reply of several lines (comment lines first) carries the sequence on its last one.
        Some(match (seq, reply.rsplit_once('\n')) {
            (Some(s), Some((comments, last))) => format!("{comments}\n[{s}] {last}"),
            (Some(s), None) => format!("[{s}] {reply}"),
            (None, _) => reply,
        })
    }

    fn request(&mut self, text: &str) -> String {
        let Ok(w) = words(text) else {
            return gateway_error(101);
        };
        // [[net] node] command: the leading numbers before the command word.
        let lead = w.iter().take_while(|x| number(x).is_some()).count().min(2);
        let (net, node) = match lead {
            2 => (number(&w[0]), number(&w[1])),
            1 => (None, number(&w[0])),
            _ => (None, None),
        };
        if net.is_some_and(|n| n != 1) {
            return gateway_error(106);
        }
        let rest: Vec<&str> = w[lead..].iter().map(String::as_str).collect();
        let Some((&cmd, args)) = rest.split_first() else {
            return gateway_error(101);
        };
        let node = match node {
            Some(n) if (1..=127).contains(&n) => Some(n as u8),
            Some(_) => return gateway_error(107),
            None => self.node,
        };
        match (cmd, args) {
            ("help", _) => HELP.to_string(),
            ("set", [what, value]) => self.set(what, value),
            ("r" | "read", [idx, sub, ty @ ..]) if ty.len() <= 1 => {
                let Some(node) = node else {
                    return gateway_error(105);
                };
                let Some(object) = Self::object(idx, sub) else {
                    return gateway_error(101);
                };
                Self::reply(self.tool.read(node, &object, ty.first().copied()))
            }
            ("w" | "write", [idx, sub, ty, value]) => {
                let Some(node) = node else {
                    return gateway_error(105);
                };
                let Some(object) = Self::object(idx, sub) else {
                    return gateway_error(101);
                };
                let r = self.tool.write(node, &object, Some(ty), value);
                Self::reply(r.map(|()| "OK".to_string()))
            }
            ("start" | "stop" | "preop" | "preoperational", []) => self.nmt(
                node,
                NmtCommand::parse(if cmd == "preoperational" {
                    "preop"
                } else {
                    cmd
                }),
            ),
            ("reset", ["node"]) => self.nmt(node, Some(NmtCommand::Reset)),
            ("reset", ["comm" | "communication"]) => self.nmt(node, Some(NmtCommand::ResetComm)),
            (c, args) if lss::is_lss(c) => self.lss(c, args),
            ("r" | "read" | "w" | "write" | "set" | "reset", _) => gateway_error(101),
            _ => gateway_error(100),
        }
    }

    /// `set WHAT VALUE`: the network (1 only), the default node, the SDO timeout in ms, block
    /// transfers on (1) or off (0).
    fn set(&mut self, what: &str, value: &str) -> String {
        match what {
            "network" => match number(value) {
                Some(1) => "OK".into(),
                Some(_) => gateway_error(106),
                None => gateway_error(101),
            },
            "node" => match number(value) {
                Some(n @ 1..=127) => {
                    self.node = Some(n as u8);
                    "OK".into()
                }
                Some(_) => gateway_error(107),
                None => gateway_error(101),
            },
            "sdo_timeout" => match number(value) {
                Some(ms) if ms > 0 => {
                    self.tool.set_timeout(Duration::from_millis(u64::from(ms)));
                    "OK".into()
                }
                _ => gateway_error(101),
            },
            "sdo_block" => match value {
                "0" | "1" => {
                    self.tool.block = if value == "1" {
                        crate::BlockMode::Always
                    } else {
                        crate::BlockMode::Never
                    };
                    "OK".into()
                }
                _ => gateway_error(101),
            },
            _ => gateway_error(101),
        }
    }

    fn nmt(&mut self, node: Option<u8>, c: Option<NmtCommand>) -> String {
        let (Some(node), Some(c)) = (node, c) else {
            return gateway_error(105);
        };
        Self::reply(self.tool.nmt(c, node).map(|()| "OK".to_string()))
    }

    fn object(idx: &str, sub: &str) -> Option<String> {
        let i = number(idx).filter(|i| *i <= 0xFFFF)?;
        let s = number(sub).filter(|s| *s <= 0xFF)?;
        Some(format!("0x{i:04X}:{s:02X}"))
    }

    fn reply(r: Result<String, ToolError>) -> String {
        match r {
            Ok(v) => v,
            Err(ToolError::Abort { code, .. }) => {
                format!("ERROR:0x{:08X} #{}", code.code(), code.description())
            }
            Err(ToolError::Timeout { .. }) => gateway_error(103),
            Err(ToolError::Usage(_)) => gateway_error(101),
            Err(_) => gateway_error(102),
        }
    }
}

/// The longest request line a gateway takes: requests are short, a written string value fits with
/// room. A longer line is answered `ERROR:101 #Syntax error` and skipped without being kept.
pub const MAX_LINE: usize = 4096;

/// Answers every request line of `input` on `output` until the input ends, taking the gateway for
/// one line at a time (several connections may share it). No line is held beyond [`MAX_LINE`].
pub fn serve(
    gateway: &std::sync::Mutex<Gateway>,
    mut input: impl std::io::BufRead,
    output: &mut dyn std::io::Write,
) -> std::io::Result<()> {
    let mut line: Vec<u8> = Vec::new();
    let mut too_long = false;
    let mut answer = |line: &mut Vec<u8>, too_long: &mut bool| -> std::io::Result<()> {
        let reply = if *too_long {
            Some(gateway_error(101))
        } else {
            let text = String::from_utf8_lossy(line);
            let mut gw = gateway
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            gw.handle(text.trim_end_matches('\r'))
        };
        line.clear();
        *too_long = false;
        if let Some(reply) = reply {
            writeln!(output, "{reply}")?;
            output.flush()?;
        }
        Ok(())
    };
    loop {
        let buf = input.fill_buf()?;
        if buf.is_empty() {
            // The input ended: a last line without its newline is a request too.
            if !line.is_empty() || too_long {
                answer(&mut line, &mut too_long)?;
            }
            return Ok(());
        }
        let newline = buf.iter().position(|&b| b == b'\n');
        let part = &buf[..newline.unwrap_or(buf.len())];
        if !too_long {
            if line.len() + part.len() > MAX_LINE {
                too_long = true;
                line.clear();
            } else {
                line.extend_from_slice(part);
            }
        }
        let taken = newline.map_or(buf.len(), |p| p + 1);
        input.consume(taken);
        if newline.is_some() {
            answer(&mut line, &mut too_long)?;
        }
    }
}
