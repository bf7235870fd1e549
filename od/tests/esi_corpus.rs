//! The ESI reader on the real-world files of `shared/corpus/esi` (see its SOURCES.md). Each fact asserted
//! here was checked by reading the XML. Every file is also written and read back: the descriptions must be
//! the same (compared through `Debug`, since some files hold NaN defaults and NaN != NaN).

use od::esi::{self, Select};
use od::object::{AccessType, ObjectKind, PdoMapping};
use od::types::DataType;
use od::value::Value;
use od::DeviceDescription;

fn corpus(name: &str) -> Vec<u8> {
    let path = format!(
        "{}/../../shared/corpus/esi/{name}",
        env!("CARGO_MANIFEST_DIR")
    );
    std::fs::read(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn read_all(name: &str) -> Vec<DeviceDescription> {
    let devices = esi::read_all(&corpus(name), name).unwrap_or_else(|e| panic!("{e}"));
    // Write → read gives the same descriptions.
    let written = esi::write_all(&devices);
    let back = esi::read_all(written.as_bytes(), "written").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(back.len(), devices.len(), "{name}");
    for (a, b) in devices.iter().zip(&back) {
        assert_eq!(
            format!("{a:?}"),
            format!("{b:?}"),
            "{name}: {} does not read back the same",
            a.identity.order_code
        );
    }
    devices
}

fn default_of(d: &DeviceDescription, index: u16, sub: u8) -> Option<Value> {
    d.dictionary
        .entry(index, sub)
        .ok()
        .and_then(|s| s.default.as_ref())
        .map(|v| v.value.clone())
}

#[test]
fn beckhoff_ek11xx_couplers_without_dictionary() {
    let ds = read_all("beckhoff-EK11xx.xml");
    assert_eq!(ds.len(), 24);
    let first = &ds[0];
    assert_eq!(first.identity.vendor_id, 2);
    assert_eq!(
        first.identity.vendor_name,
        "Beckhoff Automation GmbH & Co. KG"
    );
    assert_eq!(first.identity.order_code, "EK1100");
    assert_eq!(first.identity.product_code, 0x044C_2C52);
    assert_eq!(first.identity.revision, 0);
    assert_eq!(
        first.identity.product_name,
        "EK1100 EtherCAT Coupler (0.5A E-Bus)"
    );
    assert!(first.dictionary.is_empty(), "EK1100 maps no process data");
    assert_eq!(first.ethercat.as_ref().unwrap().group_type, "SystemBk");

    // EK1101 has no dictionary, only a TxPdo mapping 6000:01 "ID" UINT: that entry is all there is.
    let ek1101 = ds
        .iter()
        .find(|d| d.identity.order_code == "EK1101")
        .unwrap();
    assert_eq!(ek1101.identity.product_code, 0x044D_2C52);
    assert_eq!(ek1101.dictionary.len(), 1);
    let id = ek1101.dictionary.entry(0x6000, 1).unwrap();
    assert_eq!(id.name, "ID");
    assert_eq!(id.data_type, DataType::Unsigned16);
    assert_eq!(id.access.kind, AccessType::Ro);
    assert_eq!(id.pdo, PdoMapping::Tpdo);
    assert_eq!(id.default, None);

    // Several revisions of one type: the newest; ambiguous selections are refused.
    let bytes = corpus("beckhoff-EK11xx.xml");
    let ek1100 = esi::read(&bytes, "ek", Some(&Select::Name("ek1100".into()))).unwrap();
    assert_eq!(ek1100.identity.revision, 0x0012_0000);
    let e = esi::read(&bytes, "ek", None).unwrap_err();
    assert!(e.message.contains("24 devices"), "{e}");
    assert!(
        e.message
            .contains("`EK1100-0030` (product code #x044C2C52, revision #x0011001E)"),
        "{e}"
    );
    assert!(e.message.contains("choose one"), "{e}");
    let e = esi::read(&bytes, "ek", Some(&Select::ProductCode(0x044C_2C52))).unwrap_err();
    assert!(e.message.contains("choose one by type name"), "{e}");
    let ek1122 = esi::read(&bytes, "ek", Some(&Select::ProductCode(0x0462_2C52)));
    assert!(ek1122.is_err(), "EK1122 and EK1122-0008 share the code");
    let e = esi::read(&bytes, "ek", Some(&Select::Name("EL1008".into()))).unwrap_err();
    assert!(e.message.contains("no device named `EL1008`"), "{e}");
}

#[test]
fn copley_xe2() {
    let ds = read_all("copley-XE2_4.60.xml");
    assert_eq!(ds.len(), 1);
    let d = &ds[0];
    assert_eq!(d.identity.vendor_id, 0xAB);
    assert_eq!(d.identity.vendor_name, "Copley Controls");
    assert_eq!(d.identity.product_code, 0x10B0);
    assert_eq!(d.identity.revision, 0x0001_0004);
    assert_eq!(d.dictionary.len(), 661);
    // 0x2000 has the type `ARRAY [0..16383] OF UINT`: one 32 KiB value.
    let o = d.dictionary.object(0x2000).unwrap();
    assert_eq!(o.name, "Serial command handler");
    assert_eq!(o.kind, ObjectKind::Var);
    assert_eq!(o.subs[&0].data_type, DataType::OctetString);
    assert_eq!(o.subs[&0].bit_size, Some(262_144));
    assert_eq!(o.subs[&0].access.kind, AccessType::Rw);
    // 0x1C00's element names come from the object's Info/SubItems.
    let o = d.dictionary.object(0x1C00).unwrap();
    assert_eq!(o.kind, ObjectKind::Array);
    assert_eq!(o.subs[&1].name, "Comm. type, Sync Manager 0");
    // 0x1C32:01 is a UINT whose DefaultData is the single digit `2`.
    assert_eq!(
        d.dictionary.entry(0x1C32, 1).unwrap().name,
        "Synchronization type"
    );
    assert_eq!(default_of(d, 0x1C32, 1), Some(Value::Uint(2)));
    assert_eq!(
        d.dictionary.entry(0x6060, 0).unwrap().data_type,
        DataType::Integer8
    );
}

#[test]
fn elmo_gold_four_devices() {
    let ds = read_all("elmo-ECAT_00010420_V11.xml");
    assert_eq!(ds.len(), 4);
    assert!(ds.iter().all(|d| d.identity.vendor_id == 0x9A));
    assert_eq!(ds[0].identity.product_code, 0x0003_0924);
    assert_eq!(ds[0].identity.revision, 1);
    // Nine objects in the file; its TxPdo 0x1A00 also maps 0x60FD (digital inputs), which is made from
    // the PDO.
    assert_eq!(ds[0].dictionary.len(), 10);
    let inputs = ds[0].dictionary.entry(0x60FD, 0).unwrap();
    assert_eq!(
        (inputs.data_type, inputs.access.kind, inputs.pdo),
        (DataType::Integer32, AccessType::Ro, PdoMapping::Tpdo)
    );
    let drive = &ds[2];
    assert_eq!(drive.identity.revision, 0x0001_0420);
    assert_eq!(
        drive.identity.product_name,
        "Gold EtherCAT GCON Drive Rev:0x00010420"
    );
    assert_eq!(drive.dictionary.len(), 166);
    assert_eq!(
        default_of(drive, 0x1008, 0),
        Some(Value::String("Elmo Motion Control".into()))
    );
    // 0x2F45:01 is a UDINT given as two bytes `0000`.
    let e = drive.dictionary.entry(0x2F45, 1).unwrap();
    assert_eq!(e.name, "Low voltage level [mV]");
    assert_eq!(e.default.as_ref().unwrap().value, Value::Uint(0));
    let ecat = drive.ethercat.as_ref().unwrap();
    assert_eq!(ecat.rx_pdos.len(), 31);
    assert_eq!(ecat.tx_pdos.len(), 35);
    let by_code = esi::read(
        &corpus("elmo-ECAT_00010420_V11.xml"),
        "elmo",
        Some(&Select::ProductCode(0x0003_0925)),
    )
    .unwrap();
    assert_eq!(by_code.identity.revision, 0x0001_0420, "the newer revision");
}

#[test]
fn etg2001_modules_slots_iso_8859_1() {
    let ds = read_all("etg2001-ModulesSlots_CiA402.xml");
    assert_eq!(ds.len(), 1, "Descriptions/Modules are not devices");
    let d = &ds[0];
    assert_eq!(d.identity.vendor_id, 0xE000_0001);
    assert_eq!(d.identity.product_code, 0x10000);
    assert_eq!(d.identity.order_code, "Drive1");
    assert_eq!(d.identity.product_name, "DS402 Drive (Modules/Slots)");
    assert_eq!(d.dictionary.len(), 14);
    // DefaultData e3c2bf77 is little-endian.
    assert_eq!(default_of(d, 0x1018, 2), Some(Value::Uint(0x77BF_C2E3)));
    // 0x1C32:01 has the enumeration type DT0700EN16 (base UINT), default 0100.
    let sync = d.dictionary.entry(0x1C32, 1).unwrap();
    assert_eq!(sync.name, "Sync mode");
    assert_eq!(sync.data_type, DataType::Unsigned16);
    assert_eq!(default_of(d, 0x1C32, 1), Some(Value::Uint(1)));
    let ecat = d.ethercat.as_ref().unwrap();
    assert_eq!(ecat.op_modes.len(), 2);
    assert_eq!(ecat.op_modes[1].assign_activate, 0x0300);
    assert_eq!(ecat.op_modes[1].cycle_time_sync1, Some((0, 1)));
    assert_eq!(
        ecat.eeprom.as_ref().unwrap().boot_strap,
        [0x00, 0x10, 0x14, 0x02, 0x00, 0x18, 0x14, 0x02]
    );
    assert!(ecat.mailbox.as_ref().unwrap().foe);
    // Two axis slots, each taking one of the eight modules (0x100 by default); a slot's PDO indices
    // move by 16, its object indices by 0x800.
    let slots = ecat.slots.as_ref().unwrap();
    assert_eq!(
        (slots.slot_pdo_increment, slots.slot_index_increment),
        (Some(16), Some(0x800))
    );
    assert_eq!(slots.slots.len(), 2);
    assert_eq!(slots.slots[1].name, "Axis 2");
    let idents: Vec<u32> = slots.slots[0]
        .module_idents
        .iter()
        .map(|m| m.ident)
        .collect();
    assert_eq!(
        idents,
        [0x100, 0x101, 0x110, 0x111, 0x200, 0x201, 0x210, 0x211]
    );
    assert_eq!(slots.slots[0].module_idents[0].default, Some(1));
    assert_eq!(ecat.modules.len(), 8);
    let m = &ecat.modules[0];
    assert_eq!((m.ident, m.type_name.as_str()), (0x100, "Position Mode"));
    assert_eq!(m.name, "Position Mode; synchronous with process data");
    assert_eq!(
        (m.profile_no, m.dc_op_mode_name.as_str()),
        (Some(402), "Synchron")
    );
    assert_eq!(m.rx_pdos[0].index, 0x1600);
    assert!(m.rx_pdos[0].index_depend.slot && m.rx_pdos[0].entries[0].index_depend.slot);
    let target = m.dictionary.entry(0x607A, 0).unwrap();
    assert_eq!(
        (target.data_type, target.pdo),
        (DataType::Unsigned32, PdoMapping::Rpdo)
    );
}

#[test]
fn inovance_gl20_coupler_with_43_modules() {
    let ds = read_all("lcec-INOVANCE_GL20_RTU_ECT32.xml");
    assert_eq!(ds.len(), 1);
    let ecat = ds[0].ethercat.as_ref().unwrap();
    let slots = ecat.slots.as_ref().unwrap();
    assert_eq!(
        (slots.slot_index_increment, slots.slot_pdo_increment),
        (Some(0x40), Some(8))
    );
    assert!(slots.download_module_ident_list);
    assert_eq!(slots.identify_module_by, "ModuleIdent");
    let slot = &slots.slots[0];
    assert_eq!(
        (slot.name.as_str(), slot.min_instances, slot.max_instances),
        ("Terminals", 0, 32)
    );
    assert_eq!(slot.module_classes[0].class, "GL20-Digital In");
    assert_eq!(slot.module_classes[0].name, "Digital Input Terminals");
    assert_eq!(ecat.modules.len(), 43);
    let m = &ecat.modules[0];
    assert_eq!(
        (m.ident, m.class.as_str(), m.type_name.as_str()),
        (0x10F4_1064, "Digital Out", "GL20(GL20S)-0404ETP-5V")
    );
    assert_eq!(m.rx_pdos[0].index, 0x1601);
    assert_eq!(m.rx_pdos[0].exclude.len(), 2);
    assert!(m.rx_pdos[0].exclude[0].depend.slot);
}

#[test]
fn every_corpus_file_reads_and_writes_back() {
    let dir = format!("{}/../../shared/corpus/esi", env!("CARGO_MANIFEST_DIR"));
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{dir}: {e}"))
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert!(names.len() >= 40, "{names:?}");
    for name in &names {
        read_all(name);
    }
}

#[test]
fn ingenia_decimal_identity() {
    let ds = read_all("ingenia-eve-xcr-e.xml");
    assert_eq!(ds.len(), 1);
    let d = &ds[0];
    assert_eq!(d.identity.vendor_id, 0x29C);
    assert_eq!(
        d.identity.product_code, 46_338_049,
        "ProductCode in decimal"
    );
    assert_eq!(d.identity.revision, 327_700);
    assert_eq!(
        d.identity.product_name, "EVE-XCR-E",
        "LcId 1031 is all there is"
    );
    assert_eq!(d.dictionary.len(), 527);
    let op = d.dictionary.entry(0x6060, 0).unwrap();
    assert_eq!(op.name, "Operation mode");
    assert_eq!(op.data_type, DataType::Integer8);
    assert_eq!(op.access.kind, AccessType::Rw);
    assert_eq!(op.pdo, PdoMapping::Rpdo, "lower-case `r`");
    assert_eq!(default_of(d, 0x6060, 0), Some(Value::Int(0)));
}

#[test]
fn soes_lan9252_default_value_and_string() {
    let ds = read_all("soes-linux_lan9252demo.xml");
    assert_eq!(ds.len(), 1);
    let d = &ds[0];
    assert_eq!(d.identity.vendor_id, 0x1337);
    assert_eq!(d.identity.product_code, 1234);
    assert_eq!(d.dictionary.len(), 13);
    assert_eq!(default_of(d, 0x1000, 0), Some(Value::Uint(0x0190_1389)));
    assert_eq!(
        default_of(d, 0x1008, 0),
        Some(Value::String("evb9252_dig".into()))
    );
    // The object's Flags say ro, the SubItem's rw: the SubItem wins.
    let m = d.dictionary.entry(0x8000, 1).unwrap();
    assert_eq!(m.name, "Multiplier");
    assert_eq!(m.access.kind, AccessType::Rw);
}

#[test]
fn soes_xmc4_dynamic_pdos() {
    let ds = read_all("soes-rtl_xmc4_dynpdo.xml");
    assert_eq!(ds.len(), 1);
    let d = &ds[0];
    assert_eq!(d.identity.vendor_id, 0x1337);
    assert_eq!(d.identity.product_code, 0x4800);
    assert_eq!(d.dictionary.len(), 20);
    assert_eq!(default_of(d, 0x1600, 1), Some(Value::Uint(0x7000_0108)));
    let assign = d.dictionary.object(0x1C12).unwrap();
    assert_eq!(assign.kind, ObjectKind::Array);
    assert_eq!(assign.subs[&1].access.kind, AccessType::Rw);
    assert_eq!(default_of(d, 0x1C12, 2), Some(Value::Uint(0x1601)));
    assert_eq!(d.ethercat.as_ref().unwrap().rx_pdos.len(), 3);
}

#[test]
fn somanet_iso_8859_1_crlf_short_default_data() {
    let ds = read_all("somanet-CiA402-single.xml");
    assert_eq!(ds.len(), 1);
    let d = &ds[0];
    assert_eq!(d.identity.vendor_id, 0x22D2);
    assert_eq!(d.identity.vendor_name, "Synapticon GmbH");
    assert_eq!(d.identity.product_code, 0x201);
    assert_eq!(d.identity.revision, 0x0A00_0002);
    assert_eq!(d.dictionary.len(), 20);
    // 0x6040 is a UINT with DefaultData `00`.
    assert_eq!(d.dictionary.object(0x6040).unwrap().name, "Controlword");
    assert_eq!(default_of(d, 0x6040, 0), Some(Value::Uint(0)));
    // 0x1C10 is an array with no elements.
    let sm0 = d.dictionary.object(0x1C10).unwrap();
    assert_eq!(sm0.kind, ObjectKind::Array);
    assert_eq!(sm0.subs.len(), 1);
    assert_eq!(default_of(d, 0x1600, 1), Some(Value::Uint(0x6040_0010)));
}

#[test]
fn weidmueller_module_file() {
    let ds = read_all("weidmueller-UR20_IO.xml");
    assert_eq!(
        ds.len(),
        82,
        "an EtherCATModule file: one description per module"
    );
    let m = &ds[0];
    assert_eq!(m.identity.vendor_id, 560);
    assert_eq!(m.identity.vendor_name, "Weidmueller Interface");
    assert_eq!(m.identity.order_code, "UR20-4DI-P");
    assert_eq!(m.identity.product_name, "UR20-4DI-P / 1315170000");
    assert_eq!(m.identity.product_code, 0, "modules have no product code");
    assert_eq!(m.dictionary.len(), 5);
    let di1 = m.dictionary.entry(0x6000, 1).unwrap();
    assert_eq!(di1.name, "DI1");
    assert_eq!(di1.data_type, DataType::Boolean);
    assert_eq!(
        m.ethercat.as_ref().unwrap().tx_pdos[0].entries[0].data_type,
        "BOOL"
    );
}
