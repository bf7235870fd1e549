//! SII EEPROM images: the real images of the shared corpus read back, and the image generated from
//! the SMD fixture.

use od::sii::{self, category};

fn corpus(name: &str) -> Vec<u8> {
    let path = format!(
        "{}/../../shared/corpus/sii/{name}",
        env!("CARGO_MANIFEST_DIR")
    );
    std::fs::read(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// The SOES LAN9252 demo image: checksum, identity, mailbox, protocols, strings and categories as the
/// file holds them (read by eye).
#[test]
fn corpus_lan9252_demo() {
    let img = sii::parse(&corpus("soes-linux_lan9252demo.bin")).unwrap();
    assert_eq!(img.identity, [4919, 1234, 0, 0]);
    assert_eq!(img.mailbox, [0x1000, 128, 0x1080, 128]);
    assert_eq!(img.protocols, 0x000C, "CoE and FoE");
    assert_eq!(img.strings, ["evb9252_dig", "lan9252_spi", "lan9252"]);
    let kinds: Vec<u16> = img.categories.iter().map(|c| c.0).collect();
    assert_eq!(
        kinds,
        [
            category::STRINGS,
            category::GENERAL,
            category::FMMU,
            category::SYNCM
        ]
    );
    assert_eq!(img.category(category::SYNCM).unwrap().len(), 32);
}

/// The checksum of words 0–6 is CRC-8 (0x07, initial 0xFF), as both real images carry it.
#[test]
fn corpus_checksums() {
    for name in ["soes-linux_lan9252demo.bin", "soes-rtl_xmc4_dynpdo.bin"] {
        let b = corpus(name);
        assert_eq!(sii::crc8(&b[..14]), b[14], "{name}");
        assert!(sii::parse(&b).is_ok(), "{name}");
    }
    assert_eq!(
        sii::crc8(&[0x80, 0x02, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]),
        0xC6
    );
}

#[test]
fn broken_images_are_refused_with_the_place() {
    let mut b = corpus("soes-linux_lan9252demo.bin");
    assert!(sii::parse(&b[..100])
        .unwrap_err()
        .to_string()
        .contains("shorter than"));
    b[14] ^= 1;
    assert_eq!(
        sii::parse(&b).unwrap_err().to_string(),
        "bad SII image at byte 14: the checksum of words 0–6 does not match"
    );
    b[14] ^= 1;
    b[0x82] = 0xFF; // Strings length far past the end
    b[0x83] = 0x7F;
    assert!(sii::parse(&b)
        .unwrap_err()
        .to_string()
        .contains("runs past the end"));
    // Any bytes: no panic.
    for n in 0..300 {
        let junk: Vec<u8> = (0..n).map(|k| (k * 37 + n) as u8).collect();
        let _ = sii::parse(&junk);
    }
}

fn smd() -> od::DeviceDescription {
    let path = format!(
        "{}/../fixtures/smd/SMD23K-B_SMD24K.esi.xml",
        env!("CARGO_MANIFEST_DIR")
    );
    let (_, devices) = od::load::load(std::path::Path::new(&path)).unwrap();
    devices
        .into_iter()
        .find(|d| d.identity.order_code == "SMD23K-B")
        .expect("SMD23K-B")
}

/// The SMD23K-B image from its ESI: size, ESC configuration and checksum, identity with the serial,
/// the mailbox of SM0/SM1, CoE, the names, four SyncManagers, the fixed PDOs.
#[test]
fn smd_image_from_the_esi() {
    let d = smd();
    let bytes = sii::write(&d, 0x0000_1234).unwrap();
    assert_eq!(bytes.len(), 2048);
    let img = sii::parse(&bytes).unwrap();
    assert_eq!(
        &img.config[..8],
        &[0x05, 0x0C, 0x00, 0x00, 0xE8, 0x03, 0x00, 0x00]
    );
    assert_eq!(
        img.identity,
        [
            d.identity.vendor_id,
            d.identity.product_code,
            d.identity.revision,
            0x1234
        ]
    );
    let ec = d.ethercat.as_ref().unwrap();
    let sm0 = &ec.sync_managers[0];
    let sm1 = &ec.sync_managers[1];
    assert_eq!(
        img.mailbox,
        [
            sm0.start_address,
            sm0.default_size.unwrap(),
            sm1.start_address,
            sm1.default_size.unwrap()
        ]
    );
    assert_eq!(img.protocols, 0x0004, "CoE");
    assert_eq!(
        u16::from_le_bytes([bytes[0x7C], bytes[0x7D]]),
        15,
        "2 KiB = 16 KiBit"
    );
    let general = img.category(category::GENERAL).unwrap();
    assert_eq!(general.len(), 32);
    assert_eq!(img.string(general[2]), "SMD23K-B", "order code");
    assert_eq!(img.string(general[3]), d.identity.product_name);
    assert_eq!(general[5] & 0x01, 1, "CoE: SDO enabled");
    let syncm = img.category(category::SYNCM).unwrap();
    let types: Vec<u8> = syncm.chunks(8).map(|c| c[7]).collect();
    assert_eq!(types, [1, 2, 3, 4]);
    let rx = img.category(category::RXPDO).unwrap();
    assert_eq!(u16::from_le_bytes([rx[0], rx[1]]), 0x1600);
    assert_eq!(rx[2], 8, "eight output entries");
    let tx = img.category(category::TXPDO).unwrap();
    assert_eq!(u16::from_le_bytes([tx[0], tx[1]]), 0x1A00);
    assert_eq!(tx[2], 7, "seven input entries");
    // First RxPDO entry: 0x7000:01 CMD_word0, UINT (0x0006), 16 bits.
    assert_eq!(&rx[8..14], &[0x00, 0x70, 0x01, rx[11], 0x06, 16]);
    assert_eq!(img.string(rx[11]), "CMD_word0");
    assert!(img.category(category::DC).is_some());
}

/// The SyncM byte of each PDO (ETG.2010, PDO category byte 3): the SMD's PDOs name their `Sm` (2 for
/// the RxPDO, 3 for the TxPDO); a PDO the ESI assigns to no SyncManager carries 0xFF, so that a
/// master mapping from the SII (SOEM's `ecx_siiPDO` counts a PDO whose byte names a SyncManager)
/// leaves it out.
#[test]
fn a_pdo_without_a_default_sync_manager_is_written_with_0xff() {
    let mut d = smd();
    let sii_sm = |d: &od::DeviceDescription, kind: u16| {
        let img = sii::parse(&sii::write(d, 1).unwrap()).unwrap();
        img.category(kind).unwrap()[3]
    };
    assert_eq!(sii_sm(&d, category::RXPDO), 2);
    assert_eq!(sii_sm(&d, category::TXPDO), 3);
    let ec = d.ethercat.as_mut().unwrap();
    ec.rx_pdos[0].sm = None;
    ec.tx_pdos[0].sm = None;
    assert_eq!(sii_sm(&d, category::RXPDO), 0xFF);
    assert_eq!(sii_sm(&d, category::TXPDO), 0xFF);
}

/// A small image written byte by byte from ETG.1000.6 §5.4: words 0–6 the ESC configuration (PDI
/// control 0x0008, alias 0x0000) and the checksum 0x0D in byte 14 (CRC-8 0x07, initial 0xFF, of those 14
/// bytes),
/// vendor 0xABC, product 0x191, revision 0x10001, serial 7; then the categories Strings ("io",
/// "Dev"), General (group 1, order 2, name 2, CoE 0x23, flags 0x01, 120 mA), SyncM (two
/// SyncManagers), TxPDO (0x1A00 on SM3 named "io" with a 1-bit entry 0x6000:01 and an 8-bit gap),
/// End.
fn hand_image() -> Vec<u8> {
    let mut b = vec![0u8; 0x80];
    b[0] = 0x08;
    b[14] = 0x0D;
    b[0x10..0x14].copy_from_slice(&0xABCu32.to_le_bytes());
    b[0x14..0x18].copy_from_slice(&0x191u32.to_le_bytes());
    b[0x18..0x1C].copy_from_slice(&0x10001u32.to_le_bytes());
    b[0x1C..0x20].copy_from_slice(&7u32.to_le_bytes());
    b[0x7C] = 0x0F;
    b[0x7E] = 0x01;
    // Strings: 2 strings, "io" and "Dev": 1 + 3 + 4 = 8 bytes, 4 words.
    b.extend_from_slice(&[
        0x0A, 0x00, 0x04, 0x00, 2, 2, b'i', b'o', 3, b'D', b'e', b'v',
    ]);
    // General: 32 bytes, 16 words.
    let mut g = [0u8; 32];
    g[0] = 1;
    g[2] = 2;
    g[3] = 2;
    g[5] = 0x23;
    g[11] = 0x01;
    g[12] = 120;
    g[16] = 0x11;
    b.extend_from_slice(&[0x1E, 0x00, 0x10, 0x00]);
    b.extend_from_slice(&g);
    // SyncM: 2 × 8 bytes, 8 words.
    b.extend_from_slice(&[0x29, 0x00, 0x08, 0x00]);
    b.extend_from_slice(&[0x00, 0x10, 0x80, 0x00, 0x26, 0x00, 0x01, 0x01]);
    b.extend_from_slice(&[0x80, 0x11, 0x03, 0x00, 0x20, 0x00, 0x01, 0x04]);
    // TxPDO: 8 + 2 × 8 bytes, 12 words.
    b.extend_from_slice(&[0x32, 0x00, 0x0C, 0x00]);
    b.extend_from_slice(&[0x00, 0x1A, 2, 3, 0, 1, 0x11, 0x00]);
    b.extend_from_slice(&[0x00, 0x60, 0x01, 2, 0x01, 1, 0, 0]);
    b.extend_from_slice(&[0x00, 0x00, 0x00, 0, 0x00, 8, 0, 0]);
    b.extend_from_slice(&[0xFF, 0xFF]);
    b
}

/// The hand-made image read back: every field where the bytes put it.
#[test]
fn a_hand_made_image_is_read_field_by_field() {
    let b = hand_image();
    assert_eq!(sii::crc8(&b[..14]), 0x0D);
    assert_eq!(b.len(), 0x80 + 12 + 36 + 20 + 28 + 2);
    let img = sii::parse(&b).unwrap();
    assert_eq!(img.identity, [0xABC, 0x191, 0x10001, 7]);
    assert_eq!(img.strings, ["io", "Dev"]);
    assert_eq!(img.alias(), 0);
    let g = img.general().unwrap();
    assert_eq!((g.group, g.image, g.order, g.name), (1, 0, 2, 2));
    assert_eq!((g.coe, g.flags, g.current_on_ebus), (0x23, 0x01, 120));
    assert_eq!(g.physical_ports, 0x0011);
    assert_eq!(img.string(g.name), "Dev");
    assert_eq!(
        img.sync_managers(),
        [
            sii::SyncManager {
                start_address: 0x1000,
                default_size: 128,
                control: 0x26,
                enable: 1,
                kind: 1
            },
            sii::SyncManager {
                start_address: 0x1180,
                default_size: 3,
                control: 0x20,
                enable: 1,
                kind: 4
            },
        ]
    );
    assert_eq!(img.fmmus(), Vec::<u8>::new());
    let pdos = img.pdos();
    assert_eq!(pdos.len(), 1);
    let p = &pdos[0];
    assert_eq!(
        (p.tx, p.index, p.sm, p.name, p.flags),
        (true, 0x1A00, Some(3), 1, 0x0011)
    );
    assert_eq!(
        p.entries,
        [
            sii::PdoEntryRecord {
                index: 0x6000,
                sub: 1,
                name: 2,
                data_type: 1,
                bit_len: 1
            },
            sii::PdoEntryRecord {
                index: 0,
                sub: 0,
                name: 0,
                data_type: 0,
                bit_len: 8
            },
        ]
    );
}

/// How far a reader reads: to the End category's type word, each category's length taken from its
/// header; a blank EEPROM (all 0xFF) is its 64 header words and the End word; categories that never
/// end stop at 4,096 words.
#[test]
fn the_extent_of_an_image() {
    use sii::Extent::*;
    let b = hand_image();
    let n = b.len();
    assert_eq!(sii::extent(&b), Complete(n));
    let mut padded = b.clone();
    padded.resize(2048, 0xFF);
    assert_eq!(sii::extent(&padded), Complete(n), "the padding is not read");
    assert_eq!(sii::extent(&b[..0x80]), More(0x82));
    assert_eq!(sii::extent(&b[..0x82]), More(0x84), "the length word");
    // Past the Strings header: the next type word is at 0x80 + 4 + 8.
    assert_eq!(sii::extent(&b[..0x84]), More(0x8E));
    assert_eq!(sii::extent(&vec![0xFF; 2048]), Complete(0x82));
    // A category of 0xFFFE words after the header: beyond 4,096 words.
    let mut long = vec![0u8; 0x80];
    long.extend_from_slice(&[0x01, 0x00, 0xFE, 0xFF]);
    assert_eq!(sii::extent(&long), TooLong);
    assert_eq!(sii::MAX_WORDS, 4096);
}

/// IgH's `sii_write` checks: whole words, 65 words at least, the checksum, categories that end.
#[test]
fn images_checked_before_they_are_written() {
    use sii::ImageError;
    let b = hand_image();
    assert_eq!(sii::check_image(&b), Ok(()));
    assert_eq!(sii::check_image(&[]), Err(ImageError::Size { bytes: 0 }));
    assert_eq!(
        sii::check_image(&b[..b.len() - 1]),
        Err(ImageError::Size { bytes: b.len() - 1 })
    );
    assert_eq!(
        sii::check_image(&b[..128]),
        Err(ImageError::Short { words: 64 })
    );
    let mut bad = b.clone();
    bad[14] = 0x6F;
    assert_eq!(
        sii::check_image(&bad),
        Err(ImageError::Checksum {
            want: 0x0D,
            have: 0x6F
        })
    );
    assert_eq!(
        ImageError::Checksum {
            want: 0x0D,
            have: 0x6F
        }
        .to_string(),
        "the checksum of words 0–6 is 0x0D, byte 14 holds 0x6F"
    );
    // Without its End word the TxPDO category (word 0x0062: 0x40 + 6 + 18 + 10) has no next type word in the image.
    assert_eq!(
        sii::check_image(&b[..b.len() - 2]),
        Err(ImageError::Categories { word: 0x62 })
    );
    assert_eq!(
        ImageError::Categories { word: 0x62 }.to_string(),
        "the category at word 0x0062 runs past the end of the image (no End category)"
    );
}

/// The alias goes into word 4 and the checksum is made again: 0x0777 in bytes 8–9, and 0x28, the
/// CRC-8 of 08 00 00 00 00 00 00 00 77 07 00 00 00 00, in byte 14.
#[test]
fn an_alias_with_its_checksum() {
    let mut b = hand_image();
    sii::set_alias(&mut b, 0x0777);
    assert_eq!(&b[8..10], &[0x77, 0x07]);
    assert_eq!(b[14], 0x28);
    assert_eq!(sii::check_image(&b), Ok(()));
    assert_eq!(sii::parse(&b).unwrap().alias(), 0x0777);
    let mut short = vec![1u8; 10];
    sii::set_alias(&mut short, 5);
    assert_eq!(short, vec![1u8; 10], "too short: left as it is");
}

/// A slave's EEPROM read as a master reads it: a bad checksum is no reason not to read the rest, and
/// categories that run past what was read are left out.
#[test]
fn a_slave_image_is_read_leniently() {
    let mut b = hand_image();
    b[14] ^= 0xFF;
    assert!(sii::parse(&b).is_err());
    let img = sii::Image::read(&b).unwrap();
    assert_eq!(img.identity[1], 0x191);
    assert_eq!(img.config[0], 0x08);
    // Cut inside the SyncM category: Strings and General are read.
    let cut = &b[..0x80 + 12 + 36 + 10];
    let img = sii::Image::read(cut).unwrap();
    let kinds: Vec<u16> = img.categories.iter().map(|c| c.0).collect();
    assert_eq!(kinds, [category::STRINGS, category::GENERAL]);
    assert_eq!(img.strings, ["io", "Dev"]);
    // A string table cut short keeps the strings before the cut.
    let mut s = hand_image();
    s[0x84] = 3; // three strings announced, two there
    let img = sii::Image::read(&s).unwrap();
    assert_eq!(img.strings, ["io", "Dev"]);
    assert!(sii::parse(&s).is_err());
    assert!(sii::Image::read(&b[..100]).is_err());
    for n in 0..400 {
        let junk: Vec<u8> = (0..n).map(|k| (k * 53 + n) as u8).collect();
        if let Ok(img) = sii::Image::read(&junk) {
            let _ = (img.general(), img.sync_managers(), img.pdos(), img.fmmus());
        }
    }
    assert_eq!(sii::category_name(0x29), "SyncM");
    assert_eq!(sii::category_name(0x0A), "STRINGS");
    assert_eq!(sii::category_name(0x3C), "DC");
    assert_eq!(sii::category_name(0x01), "unknown");
}
