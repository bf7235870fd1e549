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
//!
//! Read back: [`parse`] checks an image strictly (a file); [`Image::read`] reads a slave's EEPROM as a
//! master does (no checksum refused, the categories that fit), with [`Image::general`],
//! [`Image::sync_managers`] and [`Image::pdos`] decoding its categories; [`extent`] says how far a
//! reader of an EEPROM of unknown size goes; [`check_image`] and [`set_alias`] are what a tool checks and
//! changes before it writes an image to a slave.

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
    parse_image(bytes, true)
}

/// Reads an image: `strict` refuses a bad checksum, a category that runs past the end and a
/// missing End category; otherwise the categories that fit are read.
fn parse_image(bytes: &[u8], strict: bool) -> Result<Image, SiiError> {
    let bad = |at: usize, what: &str| SiiError::Bad {
        at,
        what: what.to_string(),
    };
    if bytes.len() < 0x80 {
        return Err(bad(bytes.len(), "shorter than the 128-byte header"));
    }
    let mut config = [0u8; 14];
    config.copy_from_slice(&bytes[..14]);
    if strict && crc8(&config) != bytes[14] {
        return Err(bad(14, "the checksum of words 0–6 does not match"));
    }
    let u32_at =
        |o: usize| u32::from_le_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]]);
    let u16_at = |o: usize| u16::from_le_bytes([bytes[o], bytes[o + 1]]);
    let identity = [u32_at(0x10), u32_at(0x14), u32_at(0x18), u32_at(0x1C)];
    let mailbox = [u16_at(0x30), u16_at(0x32), u16_at(0x34), u16_at(0x36)];
    let protocols = u16_at(0x38);
    let mut categories = Vec::new();
    let mut at = FIRST_CATEGORY;
    loop {
        if at + 2 > bytes.len() {
            if strict {
                return Err(bad(at, "no End category"));
            }
            break;
        }
        let kind = u16_at(at);
        if kind == category::END {
            break;
        }
        if at + 4 > bytes.len() {
            if strict {
                return Err(bad(at, "category header cut off"));
            }
            break;
        }
        let len = usize::from(u16_at(at + 2)) * 2;
        let start = at + 4;
        let Some(data) = bytes.get(start..start + len) else {
            if strict {
                return Err(bad(at, "category runs past the end"));
            }
            break;
        };
        categories.push((kind, data.to_vec()));
        at = start + len;
    }
    let mut strings = Vec::new();
    if let Some((_, d)) = categories.iter().find(|(k, _)| *k == category::STRINGS) {
        let n = d.first().copied().unwrap_or(0);
        let mut p = 1;
        for _ in 0..n {
            let s = d.get(p).and_then(|l| d.get(p + 1..p + 1 + usize::from(*l)));
            let Some(s) = s else {
                if strict {
                    return Err(bad(0x80, "string table cut off"));
                }
                break;
            };
            strings.push(String::from_utf8_lossy(s).into_owned());
            p += 1 + s.len();
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

/// Words an SII image may have at most, as a master reads one (IgH's `EC_MAX_SII_SIZE`): a reader
/// that finds no End category within them takes the 64 header words only.
pub const MAX_WORDS: usize = 4096;

/// Where the categories start: word 0x40, byte 0x80.
pub const FIRST_CATEGORY: usize = 0x80;

/// How much of an SII image a reader takes ([`extent`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Extent {
    /// The image ends after this many bytes: the End category's type word is the last.
    Complete(usize),
    /// The bytes read so far do not reach the End category: read on to at least this many bytes.
    More(usize),
    /// The categories run on past [`MAX_WORDS`] without an End category.
    TooLong,
}

/// How far the SII image whose first bytes are `bytes` reaches: the header (words 0–0x3F), then each
/// category's type and length word and its data, up to the End category's type word (0xFFFF), as a
/// master reads an EEPROM it does not know the size of (ETG.1000.6 §5.4: a category is its type,
/// its length in words and its data).
pub fn extent(bytes: &[u8]) -> Extent {
    let u16_at = |o: usize| u16::from_le_bytes([bytes[o], bytes[o + 1]]);
    let mut at = FIRST_CATEGORY;
    loop {
        if at + 2 > MAX_WORDS * 2 {
            return Extent::TooLong;
        }
        if at + 2 > bytes.len() {
            return Extent::More(at + 2);
        }
        if u16_at(at) == category::END {
            return Extent::Complete(at + 2);
        }
        if at + 4 > bytes.len() {
            return Extent::More(at + 4);
        }
        at += 4 + 2 * usize::from(u16_at(at + 2));
    }
}

/// A category's name as IgH's `ethercat sii_read --verbose` writes it (ETG.1000.6 Table 19), or
/// `unknown`.
pub fn category_name(kind: u16) -> &'static str {
    match kind {
        0x000A => "STRINGS",
        0x0014 => "DataTypes",
        0x001E => "General",
        0x0028 => "FMMU",
        0x0029 => "SyncM",
        0x0032 => "TXPDO",
        0x0033 => "RXPDO",
        0x003C => "DC",
        _ => "unknown",
    }
}

/// Why an image is not written to a slave's EEPROM (the checks of IgH's `ethercat sii_write`, which
/// `--force` passes over).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ImageError {
    /// No bytes, or an odd number: an EEPROM holds 16-bit words.
    #[error("{bytes} bytes: an SII image is a positive whole number of 16-bit words")]
    Size {
        /// The bytes given.
        bytes: usize,
    },
    /// Fewer than the 64 header words and the End category.
    #[error("{words} words: an SII image has at least 65 (64 header words and the End category)")]
    Short {
        /// The words given.
        words: usize,
    },
    /// The checksum byte (word 7's low byte) is not the CRC of words 0–6.
    #[error("the checksum of words 0–6 is 0x{want:02X}, byte 14 holds 0x{have:02X}")]
    Checksum {
        /// The CRC of bytes 0–13.
        want: u8,
        /// Byte 14.
        have: u8,
    },
    /// A category runs past the end of the image, or the image ends without an End category.
    #[error("the category at word 0x{word:04X} runs past the end of the image (no End category)")]
    Categories {
        /// The word of the category's type.
        word: usize,
    },
}

/// Checks an image before it is written to a slave's EEPROM, as IgH's `ethercat sii_write` does: a
/// positive whole number of words, at least 65 of them, the checksum of words 0–6 in byte 14, and
/// categories that each end, with their next type word, inside the image.
pub fn check_image(bytes: &[u8]) -> Result<(), ImageError> {
    if bytes.is_empty() || bytes.len() % 2 == 1 {
        return Err(ImageError::Size { bytes: bytes.len() });
    }
    if bytes.len() < 0x82 {
        return Err(ImageError::Short {
            words: bytes.len() / 2,
        });
    }
    let want = crc8(&bytes[..14]);
    if want != bytes[14] {
        return Err(ImageError::Checksum {
            want,
            have: bytes[14],
        });
    }
    let u16_at = |o: usize| u16::from_le_bytes([bytes[o], bytes[o + 1]]);
    let mut at = FIRST_CATEGORY;
    while u16_at(at) != category::END {
        let next = at + 4 + 2 * usize::from(u16_at(at + 2));
        if next + 2 > bytes.len() {
            return Err(ImageError::Categories { word: at / 2 });
        }
        at = next;
    }
    Ok(())
}

/// `bytes` (an image of at least 8 words) with the configured station alias `alias` in word 4 and
/// the checksum of words 0–6 made again in byte 14, as IgH's `ethercat alias` writes them.
pub fn set_alias(bytes: &mut [u8], alias: u16) {
    if bytes.len() < 16 {
        return;
    }
    bytes[8..10].copy_from_slice(&alias.to_le_bytes());
    bytes[14] = crc8(&bytes[..14]);
}

/// The General category (ETG.1000.6 Table 21) as a master reads it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct General {
    /// String index of the group (byte 0).
    pub group: u8,
    /// String index of the image name (byte 1).
    pub image: u8,
    /// String index of the order code (byte 2).
    pub order: u8,
    /// String index of the device name (byte 3).
    pub name: u8,
    /// CoE details (byte 5): bit 0 SDO, 1 SDO Information, 2 PDO assign, 3 PDO configuration, 4
    /// upload at start-up, 5 SDO complete access.
    pub coe: u8,
    /// FoE details (byte 6).
    pub foe: u8,
    /// EoE details (byte 7).
    pub eoe: u8,
    /// SoE channels (byte 8).
    pub soe_channels: u8,
    /// DS402 channels (byte 9).
    pub ds402_channels: u8,
    /// SysmanClass (byte 10).
    pub sysman_class: u8,
    /// Flags (byte 11): bit 0 enable Safe-Op, 1 enable not-LRW.
    pub flags: u8,
    /// Current taken from the E-bus in mA (bytes 12–13, signed).
    pub current_on_ebus: i16,
    /// Physical ports (bytes 16–17): a nibble per port.
    pub physical_ports: u16,
}

impl General {
    /// The category's data; bytes it does not have read as 0.
    pub fn decode(data: &[u8]) -> General {
        let b = |k: usize| data.get(k).copied().unwrap_or(0);
        General {
            group: b(0),
            image: b(1),
            order: b(2),
            name: b(3),
            coe: b(5),
            foe: b(6),
            eoe: b(7),
            soe_channels: b(8),
            ds402_channels: b(9),
            sysman_class: b(10),
            flags: b(11),
            current_on_ebus: i16::from_le_bytes([b(12), b(13)]),
            physical_ports: u16::from_le_bytes([b(16), b(17)]),
        }
    }
}

/// One SyncManager of the SyncM category (eight bytes).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SyncManager {
    /// Physical start address.
    pub start_address: u16,
    /// Default length in bytes.
    pub default_size: u16,
    /// Control register (0x0804 + 8·n).
    pub control: u8,
    /// The enable byte: bit 0 enable, bit 2 virtual, bit 3 Op only.
    pub enable: u8,
    /// Its use: 1 mailbox out, 2 mailbox in, 3 process data out, 4 process data in, 0 unused.
    pub kind: u8,
}

/// One entry of a PDO of a TxPDO or RxPDO category.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PdoEntryRecord {
    /// Index (0 for a gap).
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
    /// String index of the name.
    pub name: u8,
    /// CoE data type index.
    pub data_type: u8,
    /// Length in bits.
    pub bit_len: u8,
}

/// One PDO of a TxPDO or RxPDO category, with its entries.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct PdoRecord {
    /// TxPDO (category 50) or RxPDO (51).
    pub tx: bool,
    /// The PDO's index.
    pub index: u16,
    /// The SyncManager it is assigned to by default; `None` for 0xFF (none).
    pub sm: Option<u8>,
    /// String index of the name.
    pub name: u8,
    /// Flags (bit 0 mandatory, bit 4 fixed, …).
    pub flags: u16,
    /// The entries.
    pub entries: Vec<PdoEntryRecord>,
}

impl Image {
    /// Reads an image as a master reads a slave's EEPROM: as [`parse`], without refusing a bad
    /// checksum (the checksum guards the ESC configuration words, not the rest), and taking the
    /// categories up to one that does not fit.
    pub fn read(bytes: &[u8]) -> Result<Image, SiiError> {
        parse_image(bytes, false)
    }

    /// The General category, when the image has one.
    pub fn general(&self) -> Option<General> {
        self.category(category::GENERAL).map(General::decode)
    }

    /// The FMMU category: one use per FMMU (1 outputs, 2 inputs, 3 mailbox state, 0 unused).
    pub fn fmmus(&self) -> Vec<u8> {
        self.category(category::FMMU)
            .map(<[u8]>::to_vec)
            .unwrap_or_default()
    }

    /// The SyncManagers of the SyncM category, in order (a last one cut short is left out).
    pub fn sync_managers(&self) -> Vec<SyncManager> {
        self.category(category::SYNCM)
            .unwrap_or_default()
            .chunks_exact(8)
            .map(|s| SyncManager {
                start_address: u16::from_le_bytes([s[0], s[1]]),
                default_size: u16::from_le_bytes([s[2], s[3]]),
                control: s[4],
                enable: s[6],
                kind: s[7],
            })
            .collect()
    }

    /// Every PDO of the TxPDO and RxPDO categories, in the order of the image (a PDO cut short is
    /// left out, with what follows it in its category).
    pub fn pdos(&self) -> Vec<PdoRecord> {
        let mut out = Vec::new();
        for (kind, data) in &self.categories {
            let tx = match *kind {
                category::TXPDO => true,
                category::RXPDO => false,
                _ => continue,
            };
            let mut at = 0;
            while let Some(h) = data.get(at..at + 8) {
                let count = usize::from(h[2]);
                let Some(body) = data.get(at + 8..at + 8 + 8 * count) else {
                    break;
                };
                out.push(PdoRecord {
                    tx,
                    index: u16::from_le_bytes([h[0], h[1]]),
                    sm: (h[3] != 0xFF).then_some(h[3]),
                    name: h[5],
                    flags: u16::from_le_bytes([h[6], h[7]]),
                    entries: body
                        .chunks_exact(8)
                        .map(|e| PdoEntryRecord {
                            index: u16::from_le_bytes([e[0], e[1]]),
                            sub: e[2],
                            name: e[3],
                            data_type: e[4],
                            bit_len: e[5],
                        })
                        .collect(),
                });
                at += 8 + 8 * count;
            }
        }
        out
    }

    /// The configured station alias (word 4).
    pub fn alias(&self) -> u16 {
        u16::from_le_bytes([self.config[8], self.config[9]])
    }
}
