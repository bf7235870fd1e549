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
