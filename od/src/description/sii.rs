//! The Slave Information Interface (SII) EEPROM image of an EtherCAT slave (ETG.1000.6 §5.4,
//! ETG.2010), generated from an ESI device, and read back.
//!
//! Layout (16-bit little-endian words): 0x00–0x06 the ESC configuration (`Eeprom/ConfigData`: PDI
//! control, PDI configuration, SYNC impulse length, extended PDI configuration, station alias), 0x07 its
//! CRC-8 (polynomial 0x07, initial 0xFF, over bytes 0–13), 0x08–0x0F vendor ID, product code,
//! revision, serial number, 0x14–0x17 the bootstrap mailbox, 0x18–0x1B the standard mailbox (receive
//! offset and size, send offset and size), 0x1C the mailbox protocols (0x0002 EoE, 0x0004 CoE, 0x0008
//! FoE), 0x3E the EEPROM size in KiBit − 1, 0x3F the version (1); from word 0x40 the categories, each
//! a type word, a length word (in words) and the data: Strings (10), General (30), FMMU (40), SyncM
//! (41), TxPDO (50), RxPDO (51), DC (60), End (0xFFFF).

use crate::device::{DeviceDescription, EthercatInfo, Pdo, PdoEntry};
use crate::types::DataType;

/// Category types (ETG.1000.6 Table 19).
pub mod category {
    /// Strings.
    pub const STRINGS: u16 = 10;
    /// General.
    pub const GENERAL: u16 = 30;
    /// FMMU.
    pub const FMMU: u16 = 40;
    /// SyncManager.
    pub const SYNCM: u16 = 41;
    /// TxPDO.
    pub const TXPDO: u16 = 50;
    /// RxPDO.
    pub const RXPDO: u16 = 51;
    /// Distributed clock.
    pub const DC: u16 = 60;
    /// End of the categories.
    pub const END: u16 = 0xFFFF;
}

/// Why an image could not be made or read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum SiiError {
    /// The description has no EtherCAT part.
    #[error("the device has no EtherCAT description (no ESI Sm/Fmmu/Eeprom data)")]
    NotEthercat,
    /// More strings than an index byte can name, or a string over 255 bytes.
    #[error("string table too large: {0}")]
    Strings(String),
    /// The image does not fit the EEPROM size of the description.
    #[error("the image takes {need} bytes, the EEPROM holds {have}")]
    TooLarge {
        /// Bytes needed.
        need: usize,
        /// EEPROM size.
        have: usize,
    },
    /// An image too short, with a bad checksum or a category that runs past the end.
    #[error("bad SII image at byte {at}: {what}")]
    Bad {
        /// Byte offset.
        at: usize,
        /// What is wrong.
        what: String,
    },
}

/// CRC-8 of the ESC configuration words (polynomial x⁸ + x² + x + 1, initial 0xFF).
pub fn crc8(bytes: &[u8]) -> u8 {
    let mut crc = 0xFFu8;
    for &b in bytes {
        crc ^= b;
        for _ in 0..8 {
            crc = if crc & 0x80 != 0 {
                (crc << 1) ^ 0x07
            } else {
                crc << 1
            };
        }
    }
    crc
}

/// The string table: index 0 is "no string".
#[derive(Default)]
struct Strings(Vec<String>);

impl Strings {
    fn index(&mut self, s: &str) -> u8 {
        if s.is_empty() {
            return 0;
        }
        if let Some(k) = self.0.iter().position(|x| x == s) {
            return (k + 1) as u8;
        }
        self.0.push(s.to_string());
        self.0.len().min(255) as u8
    }
}

fn push16(v: &mut Vec<u8>, x: u16) {
    v.extend_from_slice(&x.to_le_bytes());
}

fn category(out: &mut Vec<u8>, kind: u16, mut data: Vec<u8>) {
    if data.len() % 2 == 1 {
        data.push(0);
    }
    push16(out, kind);
    push16(out, (data.len() / 2) as u16);
    out.extend_from_slice(&data);
}

/// The CoE data type index of an ESI type name (0 when it names none): ETG.1000.6's bit arrays
/// BITARR8/16/32 have their own.
fn type_index(name: &str) -> u8 {
    match name.trim().to_ascii_uppercase().as_str() {
        "BITARR8" => 0x2D,
        "BITARR16" => 0x2E,
        "BITARR32" => 0x2F,
        _ => DataType::from_esi_name(name).map_or(0, |(t, _)| t.index() as u8),
    }
}

/// The SII entries of a PDO entry: one, with at most 255 bits (a byte holds the length); a gap longer
/// than that is several gaps of 255 bits and one of the rest.
fn sii_entries(e: &PdoEntry) -> impl Iterator<Item = (u16, u8, u8)> + '_ {
    let parts = if e.index == 0 && e.bit_len > 255 {
        usize::from(e.bit_len.div_ceil(255))
    } else {
        1
    };
    (0..parts).map(move |k| {
        let rest = e.bit_len.saturating_sub(255 * k as u16);
        (e.index, e.sub, rest.min(255) as u8)
    })
}

fn pdo_data(pdos: &[Pdo], strings: &mut Strings) -> Vec<u8> {
    let mut d = Vec::new();
    for p in pdos {
        // The count is a byte: at most 255 entries.
        let mut entries = Vec::new();
        for e in &p.entries {
            let name = strings.index(&e.name);
            let ty = type_index(&e.data_type);
            entries.extend(sii_entries(e).map(|(index, sub, bits)| (index, sub, name, ty, bits)));
        }
        entries.truncate(255);
        push16(&mut d, p.index);
        d.push(entries.len() as u8);
        // ETG.2010 (SII PDO category): the SyncManager the PDO is assigned to by default, 0xFF for
        // none (masters that map from the SII, SOEM among them, take a PDO whose number is a
        // SyncManager as assigned to it).
        d.push(p.sm.unwrap_or(0xFF));
        d.push(0); // DC synchronisation
        d.push(strings.index(&p.name));
        push16(
            &mut d,
            if p.fixed { 0x0010 } else { 0 } | if p.mandatory { 0x0001 } else { 0 },
        );
        for (index, sub, name, ty, bits) in entries {
            push16(&mut d, index);
            d.push(sub);
            d.push(name);
            d.push(ty);
            d.push(bits);
            push16(&mut d, 0);
        }
    }
    d
}

/// The SII image of `desc` with `serial` as its serial number, `Eeprom/ByteSize` bytes long (padded
/// with 0xFF).
pub fn write(desc: &DeviceDescription, serial: u32) -> Result<Vec<u8>, SiiError> {
    let ec = desc.ethercat.as_ref().ok_or(SiiError::NotEthercat)?;
    let size = ec
        .eeprom
        .as_ref()
        .map_or(2048, |e| e.byte_size.max(128) as usize);
    let mut img = header(desc, ec, serial, size);

    let mut strings = Strings::default();
    // The order code is string 1: masters that show one string per slave (SOEM) show the first.
    let order = strings.index(&desc.identity.order_code);
    let group = strings.index(&ec.group_type);
    let name = strings.index(&desc.identity.product_name);
    let txpdo = pdo_data(&ec.tx_pdos, &mut strings);
    let rxpdo = pdo_data(&ec.rx_pdos, &mut strings);
    let op_names: Vec<u8> = ec.op_modes.iter().map(|m| strings.index(&m.name)).collect();

    let general = general_data(ec, group, order, name);
    let fmmu = fmmu_data(ec);
    let syncm = syncm_data(ec);
    let dc = dc_data(ec, &op_names);
    let table = strings_data(&strings)?;
    category(&mut img, category::STRINGS, table);
    category(&mut img, category::GENERAL, general);
    category(&mut img, category::FMMU, fmmu);
    category(&mut img, category::SYNCM, syncm);
    if !txpdo.is_empty() {
        category(&mut img, category::TXPDO, txpdo);
    }
    if !rxpdo.is_empty() {
        category(&mut img, category::RXPDO, rxpdo);
    }
    if !dc.is_empty() {
        category(&mut img, category::DC, dc);
    }
    push16(&mut img, category::END);
    if img.len() > size {
        return Err(SiiError::TooLarge {
            need: img.len(),
            have: size,
        });
    }
    img.resize(size, 0xFF);
    Ok(img)
}

/// Words 0–0x3F of the image: the ESC configuration and its CRC, the identity with `serial`, the
/// mailboxes, the mailbox protocols and the EEPROM size (`size` bytes).
fn header(desc: &DeviceDescription, ec: &EthercatInfo, serial: u32, size: usize) -> Vec<u8> {
    let mut img = Vec::with_capacity(size);
    // Words 0–6: the ESC configuration, then its CRC.
    let mut config = ec
        .eeprom
        .as_ref()
        .map(|e| e.config_data.clone())
        .unwrap_or_default();
    config.resize(14, 0);
    img.extend_from_slice(&config);
    img.push(crc8(&config));
    img.push(0);
    for v in [
        desc.identity.vendor_id,
        desc.identity.product_code,
        desc.identity.revision,
        serial,
    ] {
        img.extend_from_slice(&v.to_le_bytes());
    }
    img.resize(0x28, 0); // words 0x10–0x13: delays, reserved
    let sm = |kind: &str| {
        ec.sync_managers
            .iter()
            .find(|s| s.kind == kind)
            .map(|s| (s.start_address, s.default_size.unwrap_or(0)))
            .unwrap_or((0, 0))
    };
    let (rx_off, rx_len) = sm("MBoxOut");
    let (tx_off, tx_len) = sm("MBoxIn");
    let boot = ec
        .eeprom
        .as_ref()
        .map(|e| e.boot_strap.clone())
        .unwrap_or_default();
    if boot.len() >= 8 {
        img.extend_from_slice(&boot[..8]);
    } else {
        for w in [rx_off, rx_len, tx_off, tx_len] {
            push16(&mut img, w);
        }
    }
    for w in [rx_off, rx_len, tx_off, tx_len] {
        push16(&mut img, w);
    }
    let mut protocols = 0u16;
    if let Some(m) = &ec.mailbox {
        if m.eoe {
            protocols |= 0x0002;
        }
        if m.coe.is_some() {
            protocols |= 0x0004;
        }
        if m.foe {
            protocols |= 0x0008;
        }
    }
    push16(&mut img, protocols);
    img.resize(0x7C, 0);
    push16(&mut img, ((size * 8 / 1024).max(1) - 1) as u16);
    push16(&mut img, 1);
    img
}

/// The General category, with the string indices of the group, the order code and the name.
fn general_data(ec: &EthercatInfo, group: u8, order: u8, name: u8) -> Vec<u8> {
    let mut general = vec![group, 0, order, name, 0];
    let coe = ec.mailbox.as_ref().and_then(|m| m.coe);
    general.push(coe.map_or(0, |c| {
        1 | (u8::from(c.sdo_info) << 1)
            | (u8::from(c.pdo_assign) << 2)
            | (u8::from(c.pdo_config) << 3)
            | (u8::from(c.pdo_upload) << 4)
            | (u8::from(c.complete_access) << 5)
    }));
    general.push(u8::from(ec.mailbox.as_ref().is_some_and(|m| m.foe)));
    general.push(u8::from(ec.mailbox.as_ref().is_some_and(|m| m.eoe)));
    general.extend_from_slice(&[0, 0, 0, 0]); // SoE channels, DS402 channels, SysmanClass, flags
    general.extend_from_slice(&0i16.to_le_bytes()); // current on E-bus
    general.extend_from_slice(&[group, 0]);
    general.extend_from_slice(&0x0011u16.to_le_bytes()); // ports 0 and 1: MII
    general.resize(32, 0);
    general
}

/// The FMMU category: one byte per FMMU.
fn fmmu_data(ec: &EthercatInfo) -> Vec<u8> {
    ec.fmmus
        .iter()
        .map(|f| match f.as_str() {
            "Outputs" => 1,
            "Inputs" => 2,
            "MBoxState" => 3,
            _ => 0,
        })
        .collect()
}

/// The SyncM category: eight bytes per SyncManager.
fn syncm_data(ec: &EthercatInfo) -> Vec<u8> {
    let mut syncm = Vec::new();
    for s in &ec.sync_managers {
        push16(&mut syncm, s.start_address);
        push16(&mut syncm, s.default_size.unwrap_or(0));
        syncm.push(s.control_byte);
        syncm.push(0);
        // The ESI's Virtual and OpOnly attributes are bits 2 and 3 of the enable byte.
        syncm.push(s.enable | (u8::from(s.is_virtual) << 2) | (u8::from(s.op_only) << 3));
        syncm.push(match s.kind.as_str() {
            "MBoxOut" => 1,
            "MBoxIn" => 2,
            "Outputs" => 3,
            "Inputs" => 4,
            _ => 0,
        });
    }
    syncm
}

/// The DC category: one record per operation mode, with the string indices of their names.
fn dc_data(ec: &EthercatInfo, op_names: &[u8]) -> Vec<u8> {
    let mut dc = Vec::new();
    for (m, name) in ec.op_modes.iter().zip(op_names) {
        dc.extend_from_slice(&m.cycle_time_sync0.map_or(0, |(t, _)| t).to_le_bytes());
        dc.extend_from_slice(&m.shift_time_sync0.unwrap_or(0).to_le_bytes());
        dc.extend_from_slice(&0u32.to_le_bytes()); // shift time SYNC1
        dc.extend_from_slice(&0i16.to_le_bytes()); // SYNC1 cycle factor
        push16(&mut dc, m.assign_activate);
        dc.extend_from_slice(&0i16.to_le_bytes()); // SYNC0 cycle factor
        dc.push(*name);
        dc.push(0);
        dc.extend_from_slice(&[0; 4]);
    }
    dc
}

/// The Strings category: the number of strings, then each with its length.
fn strings_data(strings: &Strings) -> Result<Vec<u8>, SiiError> {
    let mut table = vec![strings.0.len().min(255) as u8];
    for s in &strings.0 {
        if s.len() > 255 {
            return Err(SiiError::Strings(format!("{s:?} is longer than 255 bytes")));
        }
        table.push(s.len() as u8);
        table.extend_from_slice(s.as_bytes());
    }
    if strings.0.len() > 255 {
        return Err(SiiError::Strings(format!("{} strings", strings.0.len())));
    }
    Ok(table)
}

/// An SII image read back: the header values and the categories.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Image {
    /// Words 0–6 (ESC configuration).
    pub config: [u8; 14],
    /// Vendor ID, product code, revision, serial number.
    pub identity: [u32; 4],
    /// Standard mailbox: receive offset, size, send offset, size.
    pub mailbox: [u16; 4],
    /// Mailbox protocol bits.
    pub protocols: u16,
    /// The strings (index 1 first).
    pub strings: Vec<String>,
    /// Every category: type and data.
    pub categories: Vec<(u16, Vec<u8>)>,
}

impl Image {
    /// The data of the first category of `kind`.
    pub fn category(&self, kind: u16) -> Option<&[u8]> {
        self.categories
            .iter()
            .find(|(k, _)| *k == kind)
            .map(|(_, d)| d.as_slice())
    }

    /// String `index` (1-based; 0 or out of range is "").
    pub fn string(&self, index: u8) -> &str {
        index
            .checked_sub(1)
            .and_then(|k| self.strings.get(usize::from(k)))
            .map_or("", String::as_str)
    }
}

/// Reads an SII image (never panics on any input).
pub fn parse(bytes: &[u8]) -> Result<Image, SiiError> {
    let bad = |at: usize, what: &str| SiiError::Bad {
        at,
        what: what.to_string(),
    };
    if bytes.len() < 0x80 {
        return Err(bad(bytes.len(), "shorter than the 128-byte header"));
    }
    let mut config = [0u8; 14];
    config.copy_from_slice(&bytes[..14]);
    if crc8(&config) != bytes[14] {
        return Err(bad(14, "the checksum of words 0–6 does not match"));
    }
    let u32_at =
        |o: usize| u32::from_le_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]]);
    let u16_at = |o: usize| u16::from_le_bytes([bytes[o], bytes[o + 1]]);
    let identity = [u32_at(0x10), u32_at(0x14), u32_at(0x18), u32_at(0x1C)];
    let mailbox = [u16_at(0x30), u16_at(0x32), u16_at(0x34), u16_at(0x36)];
    let protocols = u16_at(0x38);
    let mut categories = Vec::new();
    let mut at = 0x80;
    loop {
        if at + 2 > bytes.len() {
            return Err(bad(at, "no End category"));
        }
        let kind = u16_at(at);
        if kind == category::END {
            break;
        }
        if at + 4 > bytes.len() {
            return Err(bad(at, "category header cut off"));
        }
        let len = usize::from(u16_at(at + 2)) * 2;
        let start = at + 4;
        let data = bytes
            .get(start..start + len)
            .ok_or_else(|| bad(at, "category runs past the end"))?;
        categories.push((kind, data.to_vec()));
        at = start + len;
    }
    let mut strings = Vec::new();
    if let Some((_, d)) = categories.iter().find(|(k, _)| *k == category::STRINGS) {
        let n = d.first().copied().unwrap_or(0);
        let mut p = 1;
        for _ in 0..n {
            let l = usize::from(*d.get(p).ok_or_else(|| bad(0x80, "string table cut off"))?);
            let s = d
                .get(p + 1..p + 1 + l)
                .ok_or_else(|| bad(0x80, "string table cut off"))?;
            strings.push(String::from_utf8_lossy(s).into_owned());
            p += 1 + l;
        }
    }
    Ok(Image {
        config,
        identity,
        mailbox,
        protocols,
        strings,
        categories,
    })
}
