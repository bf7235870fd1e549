//! The output layouts of IgH's `ethercat` tool (the EtherLab master's command line), for the EtherCAT
//! commands of the same names: `slaves` (one line per slave, or `--verbose` blocks), `pdos`, `xml`,
//! `cstruct`, `sii-read --verbose`, and the register values of `reg-read` with their `--type`s. Pure
//! functions from what was read to text, so that each layout is pinned by a test against IgH's
//! format worked out by hand; the commands ([`crate::cmd::ethercat`]) read and print.
//!
//! Where IgH's tool counts positions from 0, these count from 1, as every command of this tool does
//! (`read 1 …` is the first slave): `=== Slave 1 ===`, `<!-- Slave 1 -->`, `slave_1_pdo_entries`.
//! Hexadecimal is lower-case where IgH's is (its C++ streams' `hex`).

use std::fmt::Write as _;

/// One PDO entry as `pdos`, `xml` and `cstruct` show it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EntryConfig {
    /// Index (0 for a gap).
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
    /// Length in bits.
    pub bit_len: u8,
    /// Name ("" when none is known).
    pub name: String,
}

/// One PDO of a SyncManager, with its entries.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PdoConfig {
    /// The PDO's index.
    pub index: u16,
    /// Name ("" when none is known).
    pub name: String,
    /// The mapped entries.
    pub entries: Vec<EntryConfig>,
}

/// One SyncManager as the SII describes it, with the PDOs assigned to it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SyncConfig {
    /// Its number.
    pub index: u8,
    /// Physical start address.
    pub start_address: u16,
    /// Default length in bytes.
    pub default_size: u16,
    /// Control register.
    pub control: u8,
    /// The SII's enable byte.
    pub enable: u8,
    /// The PDOs assigned to it.
    pub pdos: Vec<PdoConfig>,
}

impl SyncConfig {
    /// Written by the master (control register bit 2): its PDOs are RxPDOs, outputs.
    pub fn output(&self) -> bool {
        self.control & 0x04 != 0
    }
}

/// A slave's identity, names and SyncManagers: what `xml` and `cstruct` are made of.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SlaveConfig {
    /// 1-based position.
    pub position: u16,
    /// Vendor ID, product code, revision, serial number.
    pub identity: [u32; 4],
    /// Order code (SII General's order string).
    pub order: String,
    /// Device name (SII General's name string).
    pub name: String,
    /// The SyncManagers in order.
    pub syncs: Vec<SyncConfig>,
}

/// Every PDO of an SII image's TxPDO and RxPDO categories, with the SyncManager its record names
/// (`None` for 0xFF), its name and its entries' names from the Strings category.
pub fn sii_pdos(image: &od::sii::Image) -> Vec<(Option<u8>, PdoConfig)> {
    image
        .pdos()
        .into_iter()
        .map(|p| {
            let pdo = PdoConfig {
                index: p.index,
                name: image.string(p.name).to_string(),
                entries: p
                    .entries
                    .iter()
                    .map(|e| EntryConfig {
                        index: e.index,
                        sub: e.sub,
                        bit_len: e.bit_len,
                        name: image.string(e.name).to_string(),
                    })
                    .collect(),
            };
            (p.sm, pdo)
        })
        .collect()
}

/// The SyncManagers and PDOs of an SII image as IgH's master takes them from it: each SyncManager
/// of the SyncM category, and each PDO of the TxPDO and RxPDO categories with the SyncManager its
/// SII record names (a PDO of none, 0xFF, or of a SyncManager the image does not have, is left out),
/// names from the Strings category.
pub fn sii_syncs(image: &od::sii::Image) -> Vec<SyncConfig> {
    let mut syncs: Vec<SyncConfig> = image
        .sync_managers()
        .iter()
        .enumerate()
        .map(|(k, s)| SyncConfig {
            index: k as u8,
            start_address: s.start_address,
            default_size: s.default_size,
            control: s.control,
            enable: s.enable,
            pdos: Vec::new(),
        })
        .collect();
    for (sm, pdo) in sii_pdos(image) {
        if let Some(sync) = sm.and_then(|sm| syncs.get_mut(usize::from(sm))) {
            sync.pdos.push(pdo);
        }
    }
    syncs
}

/// `pdos` for one slave, in IgH's layout: each SyncManager, its PDOs and their entries.
///
/// ```text
/// SM2: PhysAddr 0x1100, DefaultSize    3, ControlRegister 0x64, Enable 1
///   RxPDO 0x1600 "Outputs"
///     PDO entry 0x7000:01,  1 bit, "Output 1"
/// ```
pub fn pdos(syncs: &[SyncConfig]) -> String {
    let mut s = String::new();
    for (k, sync) in syncs.iter().enumerate() {
        let _ = writeln!(
            s,
            "SM{k}: PhysAddr 0x{:04x}, DefaultSize {:4}, ControlRegister 0x{:02x}, Enable {}",
            sync.start_address, sync.default_size, sync.control, sync.enable
        );
        let dir = if sync.output() { 'R' } else { 'T' };
        for p in &sync.pdos {
            let _ = writeln!(s, "  {dir}xPDO 0x{:04x} \"{}\"", p.index, p.name);
            for e in &p.entries {
                let _ = writeln!(
                    s,
                    "    PDO entry 0x{:04x}:{:02x}, {:2} bit, \"{}\"",
                    e.index, e.sub, e.bit_len, e.name
                );
            }
        }
    }
    s
}

/// `text` without the control characters XML 1.0 has no place for.
fn xml_chars(text: &str) -> String {
    text.chars()
        .filter(|c| !c.is_control() || matches!(c, '\t' | '\n' | '\r'))
        .collect()
}

/// Text for an XML element: escaped, and without the control characters XML 1.0 has no place for.
fn xml_text(text: &str) -> String {
    od::xml::escape(&xml_chars(text)).into_owned()
}

/// The data type IgH's `ethercat xml` gives an entry of `bits` bits: BOOL for one, UINT8 to UINT64
/// for whole bytes up to 8, STRING(n) for more, BITn otherwise.
fn xml_data_type(bits: u8) -> String {
    match bits {
        1 => "BOOL".to_string(),
        b if b % 8 == 0 && b <= 64 => format!("UINT{b}"),
        b if b % 8 == 0 => format!("STRING({})", b / 8),
        b => format!("BIT{b}"),
    }
}

/// One slave's `EtherCATInfo` in IgH's layout, each line after `indent` (two spaces inside an
/// `EtherCATInfoList`).
fn xml_slave(s: &mut String, slave: &SlaveConfig, indent: &str) {
    let [vendor, product, revision, _] = slave.identity;
    let mut line = |text: String| {
        s.push_str(indent);
        s.push_str(&text);
        s.push('\n');
    };
    line("<EtherCATInfo>".into());
    line(format!("  <!-- Slave {} -->", slave.position));
    line("  <Vendor>".into());
    line(format!("    <Id>{vendor}</Id>"));
    line("  </Vendor>".into());
    line("  <Descriptions>".into());
    line("    <Devices>".into());
    line("      <Device>".into());
    line(format!(
        "        <Type ProductCode=\"#x{product:08x}\" RevisionNo=\"#x{revision:08x}\">{}</Type>",
        xml_text(&slave.order)
    ));
    if !slave.name.is_empty() {
        // Nothing is escaped in a CDATA section, which ends at "]]>": one in the name is split over
        // two sections.
        let name = xml_chars(&slave.name).replace("]]>", "]]]]><![CDATA[>");
        line(format!("        <Name><![CDATA[{name}]]></Name>"));
    }
    for sync in &slave.syncs {
        line(format!(
            "        <Sm Enable=\"{}\" StartAddress=\"#x{:x}\" ControlByte=\"#x{:x}\" DefaultSize=\"{}\" />",
            sync.enable, sync.start_address, sync.control, sync.default_size
        ));
    }
    for (k, sync) in slave.syncs.iter().enumerate() {
        let kind = if sync.output() { "RxPdo" } else { "TxPdo" };
        for p in &sync.pdos {
            line(format!(
                "        <{kind} Sm=\"{k}\" Fixed=\"1\" Mandatory=\"1\">"
            ));
            line(format!("          <Index>#x{:04x}</Index>", p.index));
            line(format!("          <Name>{}</Name>", xml_text(&p.name)));
            for e in &p.entries {
                line("          <Entry>".into());
                line(format!("            <Index>#x{:04x}</Index>", e.index));
                if e.index != 0 {
                    line(format!("            <SubIndex>{}</SubIndex>", e.sub));
                }
                line(format!("            <BitLen>{}</BitLen>", e.bit_len));
                if e.index != 0 {
                    line(format!("            <Name>{}</Name>", xml_text(&e.name)));
                    line(format!(
                        "            <DataType>{}</DataType>",
                        xml_data_type(e.bit_len)
                    ));
                }
                line("          </Entry>".into());
            }
            line(format!("        </{kind}>"));
        }
    }
    line("      </Device>".into());
    line("    </Devices>".into());
    line("  </Descriptions>".into());
    line("</EtherCATInfo>".into());
}

/// `xml`: an ESI of what the slaves report, in IgH's layout; several slaves as an
/// `EtherCATInfoList`, each `EtherCATInfo` indented by two spaces. Names are escaped (IgH writes
/// them as they are).
pub fn xml(slaves: &[SlaveConfig]) -> String {
    let mut s = String::from("<?xml version=\"1.0\" ?>\n");
    let list = slaves.len() > 1;
    if list {
        s.push_str("<EtherCATInfoList>\n");
    }
    for slave in slaves {
        xml_slave(&mut s, slave, if list { "  " } else { "" });
    }
    if list {
        s.push_str("</EtherCATInfoList>\n");
    }
    s
}

/// A name inside a C comment: a `*/` in it would end the comment.
fn c_comment(name: &str) -> String {
    name.replace("*/", "* /")
}

/// `cstruct`: the slave's SyncManagers, PDOs and entries as the C arrays IgH's application interface
/// takes (`ec_pdo_entry_info_t`, `ec_pdo_info_t`, `ec_sync_info_t`), in IgH's layout; nothing for a
/// slave without SyncManagers.
pub fn cstruct(slave: &SlaveConfig) -> String {
    if slave.syncs.is_empty() {
        return String::new();
    }
    let id = format!("slave_{}_", slave.position);
    let (mut syncs, mut pdos, mut entries) = (String::new(), String::new(), String::new());
    let (mut pdo_pos, mut entry_pos) = (0usize, 0usize);
    for sync in &slave.syncs {
        let list = if sync.pdos.is_empty() {
            "NULL".to_string()
        } else {
            format!("{id}pdos + {pdo_pos}")
        };
        let _ = writeln!(
            syncs,
            "    {{{}, {}, {}, {list}, {}}},",
            sync.index,
            if sync.output() {
                "EC_DIR_OUTPUT"
            } else {
                "EC_DIR_INPUT"
            },
            sync.pdos.len(),
            if sync.control & 0x40 != 0 {
                "EC_WD_ENABLE"
            } else {
                "EC_WD_DISABLE"
            }
        );
        pdo_pos += sync.pdos.len();
        for p in &sync.pdos {
            let list = if p.entries.is_empty() {
                "NULL".to_string()
            } else {
                format!("{id}pdo_entries + {entry_pos}")
            };
            let _ = write!(
                pdos,
                "    {{0x{:04x}, {}, {list}}},",
                p.index,
                p.entries.len()
            );
            if !p.name.is_empty() {
                let _ = write!(pdos, " /* {} */", c_comment(&p.name));
            }
            pdos.push('\n');
            entry_pos += p.entries.len();
            for e in &p.entries {
                let _ = write!(
                    entries,
                    "    {{0x{:04x}, 0x{:02x}, {}}},",
                    e.index, e.sub, e.bit_len
                );
                if !e.name.is_empty() {
                    let _ = write!(entries, " /* {} */", c_comment(&e.name));
                }
                entries.push('\n');
            }
        }
    }
    let [vendor, product, revision, _] = slave.identity;
    let mut s = format!("/* Master 0, Slave {}", slave.position);
    if !slave.order.is_empty() {
        let _ = write!(s, ", \"{}\"", c_comment(&slave.order));
    }
    let _ = write!(
        s,
        "\n * Vendor ID:       0x{vendor:08x}\n * Product code:    0x{product:08x}\n \
         * Revision number: 0x{revision:08x}\n */\n\n"
    );
    if entry_pos > 0 {
        let _ = write!(
            s,
            "ec_pdo_entry_info_t {id}pdo_entries[] = {{\n{entries}}};\n\n"
        );
    }
    if pdo_pos > 0 {
        let _ = write!(s, "ec_pdo_info_t {id}pdos[] = {{\n{pdos}}};\n\n");
    }
    let _ = write!(
        s,
        "ec_sync_info_t {id}syncs[] = {{\n{syncs}    {{0xff}}\n}};\n\n"
    );
    s
}

/// Bytes as IgH's tool lists them: two lower-case hex digits each, 16 to a line, each line after
/// two spaces and a line break (the first line break follows the caption).
fn hex_lines(s: &mut String, bytes: &[u8]) {
    for (k, b) in bytes.iter().enumerate() {
        s.push_str(if k % 16 == 0 { "\n  " } else { " " });
        let _ = write!(s, "{b:02x}");
    }
    s.push('\n');
}

/// `sii-read --verbose`: the 64 header words, then each category with its type, name and length in
/// words, up to the End category, as IgH's `ethercat sii_read --verbose` lists them. `bytes` is the
/// image as read (up to and with the End category's type word).
pub fn sii_listing(bytes: &[u8]) -> String {
    let mut s = String::from("SII Area:");
    hex_lines(&mut s, &bytes[..bytes.len().min(0x80)]);
    let u16_at = |o: usize| {
        bytes
            .get(o..o + 2)
            .map(|w| u16::from_le_bytes([w[0], w[1]]))
    };
    let mut at = od::sii::FIRST_CATEGORY;
    while let Some(kind) = u16_at(at).filter(|k| *k != od::sii::category::END) {
        let _ = write!(
            s,
            "SII Category 0x{kind:04x} ({})",
            od::sii::category_name(kind)
        );
        let Some(words) = u16_at(at + 2) else {
            s.push_str(": cut off\n");
            break;
        };
        let _ = write!(s, ", {words} words");
        let data = at + 4..at + 4 + 2 * usize::from(words);
        let Some(d) = bytes.get(data.clone()) else {
            s.push_str(": cut off\n");
            break;
        };
        hex_lines(&mut s, d);
        at = data.end;
    }
    s
}

mod slaves;
mod values;

pub use slaves::{identity_name, next_slaves, slaves_list, slaves_verbose, EscInfo, SlaveLine};
pub use values::{parse_number, RegType};

#[cfg(test)]
mod tests;
