//! `slaves` in IgH's layouts: one line per slave, and the `--verbose` block of each.

use std::fmt::Write as _;

/// One slave as the one-line `slaves` shows it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SlaveLine {
    /// 1-based position.
    pub position: u16,
    /// The configured station alias (SII word 4; 0 for none).
    pub alias: u16,
    /// The AL state in IgH's words ([`crate::ethercat::state_name`]).
    pub state: String,
    /// The slave could not be read (its SII): IgH's error flag `E`, else `+`.
    pub error: bool,
    /// The device name of its SII, or `0xVENDOR:0xPRODUCT` without one.
    pub name: String,
}

/// The name IgH shows for a slave without a name in its SII: vendor ID and product code in hex.
pub fn identity_name(vendor: u32, product: u32) -> String {
    format!("0x{vendor:08x}:0x{product:08x}")
}

/// `slaves` in IgH's one-line layout: the position, the alias of the slave or of the last slave
/// before it with one (0 for none) and the position relative to that slave, the state, the error
/// flag and the name, each column as wide as its widest entry.
///
/// ```text
/// 1  0:0  PREOP  +  EL3102 2K. Ana. Eingang
/// ```
pub fn slaves_list(lines: &[SlaveLine]) -> String {
    let mut rows = Vec::new();
    let (mut last_alias, mut relative) = (0u16, 0u32);
    for l in lines {
        if l.alias != 0 {
            last_alias = l.alias;
            relative = 0;
        }
        rows.push((
            l.position.to_string(),
            last_alias.to_string(),
            relative.to_string(),
            l,
        ));
        relative += 1;
    }
    let width = |f: fn(&(String, String, String, &SlaveLine)) -> usize| {
        rows.iter().map(f).max().unwrap_or(0)
    };
    let wp = width(|r| r.0.len());
    let wa = width(|r| r.1.len());
    let wr = width(|r| r.2.len());
    let ws = width(|r| r.3.state.len());
    let mut s = String::new();
    for (pos, alias, rel, l) in &rows {
        let flag = if l.error { 'E' } else { '+' };
        let _ = writeln!(
            s,
            "{pos:>wp$}  {alias:>wa$}:{rel:<wr$}  {:<ws$}  {flag}  {}",
            l.state, l.name
        );
    }
    s
}

/// What `slaves --verbose` shows of a slave's ESC besides its SII.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct EscInfo {
    /// Port descriptor (0x0007): two bits per port, 0 not implemented, 1 not configured, 2 E-bus,
    /// 3 MII.
    pub ports: u8,
    /// ESC features (0x0008).
    pub features: u16,
    /// The system time register (0x0910) answered a read.
    pub dc_system_time: bool,
    /// DL status (0x0110).
    pub dl_status: u16,
    /// The slave on each port (1-based position), as [`next_slaves`] finds them.
    pub next: [Option<u16>; 4],
}

/// Which slave is behind each port of each slave of a chain whose DL statuses (0x0110) are `dl`,
/// as IgH's master works out the topology: port 0 leads to the slave before (none for the first);
/// the other open ports, in the order 3, 1, 2, each lead to the next slave in the chain's order,
/// whose own ports are followed first; the walk starts at the first slave.
pub fn next_slaves(dl: &[u16]) -> Vec<[Option<u16>; 4]> {
    fn visit(dl: &[u16], out: &mut [[Option<u16>; 4]], up: Option<u16>, at: &mut usize) -> bool {
        let this = *at;
        out[this][0] = up;
        for port in [3usize, 1, 2] {
            let closed = dl[this] & (1 << (8 + 2 * port)) != 0;
            if !closed {
                *at += 1;
                if *at >= dl.len() {
                    return false;
                }
                out[this][port] = Some(*at as u16 + 1);
                if !visit(dl, out, Some(this as u16 + 1), at) {
                    return false;
                }
            }
        }
        true
    }
    let mut out = vec![[None; 4]; dl.len()];
    if !dl.is_empty() {
        // A chain the rules do not describe (an open port with no slave left for it) is left
        // where the walk stopped, as IgH's master leaves it.
        visit(dl, &mut out, None, &mut 0);
    }
    out
}

fn yes(b: bool) -> &'static str {
    if b {
        "yes"
    } else {
        "no"
    }
}

/// The DL information and the port table of `slaves --verbose`.
fn esc_lines(s: &mut String, esc: &EscInfo) {
    let dc = esc.features & 0x04 != 0;
    let _ = writeln!(s, "DL information:");
    let _ = writeln!(s, "  FMMU bit operation: {}", yes(esc.features & 0x01 != 0));
    let _ = write!(s, "  Distributed clocks: ");
    if !dc {
        let _ = writeln!(s, "no");
    } else if esc.dc_system_time {
        let range = if esc.features & 0x08 != 0 { 64 } else { 32 };
        let _ = writeln!(s, "yes, {range} bit");
    } else {
        let _ = writeln!(s, "yes, delay measurement only");
    }
    let _ = writeln!(s, "Port  Type  Link  Loop    Signal  NextSlave");
    for port in 0..4 {
        let kind = match (esc.ports >> (2 * port)) & 0x03 {
            0 => "N/A",
            1 => "N/C",
            2 => "EBUS",
            _ => "MII",
        };
        let bit = |n: usize| esc.dl_status & (1 << n) != 0;
        let link = if bit(4 + port) { "up" } else { "down" };
        let lp = if bit(8 + 2 * port) { "closed" } else { "open" };
        let signal = yes(bit(9 + 2 * port));
        let next = esc.next[port].map_or("-".to_string(), |p| p.to_string());
        let _ = writeln!(
            s,
            "   {port}  {kind:<4}  {link:<4}  {lp:<6}  {signal:<6}  {next:>9}"
        );
    }
}

/// The Mailboxes block: bootstrap and standard mailboxes (SII words 0x14–0x1B) and the protocols
/// (word 0x1C), when the slave has any.
fn mailbox_lines(s: &mut String, sii: &[u8]) {
    let w = |k: usize| {
        sii.get(2 * k..2 * k + 2)
            .map_or(0, |b| u16::from_le_bytes([b[0], b[1]]))
    };
    let protocols = w(0x1C);
    if protocols == 0 {
        return;
    }
    let _ = writeln!(s, "Mailboxes:");
    let _ = writeln!(
        s,
        "  Bootstrap RX: 0x{:04x}/{}, TX: 0x{:04x}/{}",
        w(0x14),
        w(0x15),
        w(0x16),
        w(0x17)
    );
    let _ = writeln!(
        s,
        "  Standard  RX: 0x{:04x}/{}, TX: 0x{:04x}/{}",
        w(0x18),
        w(0x19),
        w(0x1A),
        w(0x1B)
    );
    let names = [
        (0x01, "AoE"),
        (0x02, "EoE"),
        (0x04, "CoE"),
        (0x08, "FoE"),
        (0x10, "SoE"),
        (0x20, "VoE"),
    ];
    let list: Vec<&str> = names
        .iter()
        .filter(|(bit, _)| protocols & bit != 0)
        .map(|(_, n)| *n)
        .collect();
    let _ = writeln!(s, "  Supported protocols: {}", list.join(", "));
}

/// The General block: its strings, the CoE details (for a CoE slave), the flags and the current.
fn general_lines(s: &mut String, image: &od::sii::Image, g: &od::sii::General) {
    let _ = writeln!(s, "General:");
    let _ = writeln!(s, "  Group: {}", image.string(g.group));
    let _ = writeln!(s, "  Image name: {}", image.string(g.image));
    let _ = writeln!(s, "  Order number: {}", image.string(g.order));
    let _ = writeln!(s, "  Device name: {}", image.string(g.name));
    if image.protocols & 0x04 != 0 {
        let c = |bit: u8| yes(g.coe & bit != 0);
        let _ = writeln!(s, "  CoE details:");
        let _ = writeln!(s, "    Enable SDO: {}", c(0x01));
        let _ = writeln!(s, "    Enable SDO Info: {}", c(0x02));
        let _ = writeln!(s, "    Enable PDO Assign: {}", c(0x04));
        let _ = writeln!(s, "    Enable PDO Configuration: {}", c(0x08));
        let _ = writeln!(s, "    Enable Upload at startup: {}", c(0x10));
        let _ = writeln!(s, "    Enable SDO complete access: {}", c(0x20));
    }
    let _ = writeln!(s, "  Flags:");
    let _ = writeln!(s, "    Enable SafeOp: {}", yes(g.flags & 0x01 != 0));
    let _ = writeln!(s, "    Enable notLRW: {}", yes(g.flags & 0x02 != 0));
    let _ = writeln!(s, "  Current consumption: {} mA", g.current_on_ebus);
}

/// `slaves --verbose` for one slave, in IgH's layout: its alias (when it has one), state, error
/// flag, SII identity, DL information and ports, mailboxes and General category. `sii` is the
/// image as read from its EEPROM (empty when it could not be read).
///
/// What IgH's master measures itself while it scans the chain, and a look at the chain cannot, is
/// left out: the DC system time transmission delay and the ports' receive times.
pub fn slaves_verbose(line: &SlaveLine, sii: &[u8], esc: &EscInfo) -> String {
    let mut s = format!("=== Slave {} ===\n", line.position);
    if line.alias != 0 {
        let _ = writeln!(s, "Alias: {}", line.alias);
    }
    let _ = writeln!(s, "State: {}", line.state);
    let _ = writeln!(s, "Flag: {}", if line.error { 'E' } else { '+' });
    let image = od::sii::Image::read(sii).ok();
    let [vendor, product, revision, serial] = image.as_ref().map_or([0; 4], |i| i.identity);
    let _ = writeln!(s, "Identity:");
    let _ = writeln!(s, "  Vendor Id:       0x{vendor:08x}");
    let _ = writeln!(s, "  Product code:    0x{product:08x}");
    let _ = writeln!(s, "  Revision number: 0x{revision:08x}");
    let _ = writeln!(s, "  Serial number:   0x{serial:08x}");
    esc_lines(&mut s, esc);
    mailbox_lines(&mut s, sii);
    if let Some((image, g)) = image.as_ref().and_then(|i| Some((i, i.general()?))) {
        general_lines(&mut s, image, &g);
    }
    s
}
