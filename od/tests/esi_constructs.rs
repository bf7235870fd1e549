//! Constructs of real vendor ESI files that the established tools load, each reproduced in a small file of
//! its own: what the reader makes of it (exact model values) and the warning it gives (exact text, line
//! and column). Each file is also written and read back.

use od::esi;
use od::object::ObjectKind;
use od::report::{Finding, Reading};
use od::types::DataType;
use od::value::Value;
use od::DeviceDescription;

/// Reads `text`, checks that write → read gives the same descriptions and no warnings, and answers the
/// reading.
fn read(text: &str) -> Reading {
    let reading = esi::read_file(text.as_bytes(), "t.xml").unwrap_or_else(|e| panic!("{e}"));
    let written = esi::write_all(&reading.devices);
    let back =
        esi::read_file(written.as_bytes(), "w.xml").unwrap_or_else(|e| panic!("{e}\n{written}"));
    assert_eq!(
        format!("{:?}", back.devices),
        format!("{:?}", reading.devices),
        "write → read changes the descriptions:\n{written}"
    );
    assert_eq!(
        back.findings,
        vec![],
        "what was written reads without warnings:\n{written}"
    );
    reading
}

fn one(text: &str) -> (DeviceDescription, Vec<Finding>) {
    let r = read(text);
    assert_eq!(r.devices.len(), 1);
    (r.devices.into_iter().next().unwrap(), r.findings)
}

/// `line:column: text` of each finding (with the address when there is one).
fn said(findings: &[Finding]) -> Vec<String> {
    findings
        .iter()
        .map(|f| {
            let p = f.position.expect("every reader warning has a position");
            format!("{}:{}: {f}", p.line, p.column)
        })
        .collect()
}

/// A file whose `Profile` (objects from line 7) and PDOs (from line 9) are given.
fn device(objects: &str, pdos: &str) -> String {
    format!(
        "<?xml version=\"1.0\"?>\n<EtherCATInfo>\n<Vendor><Id>1</Id><Name>V</Name></Vendor>\n\
         <Descriptions><Groups/><Devices><Device>\n<Type ProductCode=\"1\" RevisionNo=\"1\">T</Type><Name>N</Name>\n\
         <Profile><Dictionary><DataTypes/><Objects>\n{objects}\n</Objects></Dictionary></Profile>\n{pdos}\n\
         </Device></Devices></Descriptions>\n</EtherCATInfo>\n"
    )
}

// ---------------------------------------------------------------------------------------------------------
// Numbers and values.

#[test]
fn an_index_with_two_hexadecimal_prefixes_reads_as_the_number() {
    let pdos = "<TxPdo Sm=\"3\"><Index>#x1A00</Index><Name>In</Name>\n\
                <Entry><Index>#x0x6041</Index><SubIndex>0</SubIndex><BitLen>16</BitLen><Name>Status</Name><DataType>UINT</DataType></Entry>\n\
                </TxPdo>";
    let text = device(
        "<Object><Index>#x6041</Index><Name>Status</Name><Type>UINT</Type><Flags><Access>ro</Access><PdoMapping>T</PdoMapping></Flags></Object>",
        pdos,
    );
    let (d, findings) = one(&text);
    let entry = &d.ethercat.as_ref().unwrap().tx_pdos[0].entries[0];
    assert_eq!((entry.index, entry.sub, entry.bit_len), (0x6041, 0, 16));
    assert_eq!(
        said(&findings),
        ["10:15: warning: `#x0x6041` in <Entry>/<Index> has two hexadecimal prefixes; read as #x6041"]
    );
}

#[test]
fn limits_outside_the_type_are_dropped() {
    // A DINT with the UDINT range copied into it (MinValue -4294967295), a UINT whose MinData has a
    // nonzero byte beyond its size, and a MaxData that is no hexadecimal.
    let objects = "<Object><Index>#x6064</Index><Name>Position</Name><Type>DINT</Type>\n\
                   <Info><MinValue>-4294967295</MinValue><MaxValue>1000</MaxValue></Info></Object>\n\
                   <Object><Index>#x2000</Index><Name>Speed</Name><Type>UINT</Type><Info><MinData>000001</MinData><MaxData>zz</MaxData><DefaultData>0500</DefaultData></Info></Object>";
    let (d, findings) = one(&device(objects, ""));
    let pos = d.dictionary.entry(0x6064, 0).unwrap();
    assert_eq!(pos.low, None);
    assert_eq!(pos.high, Some(Value::Int(1000)));
    let speed = d.dictionary.entry(0x2000, 0).unwrap();
    assert_eq!((&speed.low, &speed.high), (&None, &None));
    assert_eq!(speed.default.as_ref().unwrap().value, Value::Uint(5));
    assert_eq!(
        said(&findings),
        [
            "8:17: warning: object #x6064: expected a DINT value -2147483648..2147483647 in <MinValue>, found `-4294967295`; the limit is dropped",
            "9:80: warning: object #x2000: <MinData> is not a UINT: UNSIGNED16 takes 2 bytes, got 3; the limit is dropped",
            "9:105: warning: expected hexadecimal bytes like 0A1B in <MaxData>, found `zz`; the limit is dropped",
        ]
    );
}

/// `Info/Unit` (ETG.1004 unit codes, as Beckhoff's EL9xxx and ELM37xx give them) is kept, of a VAR
/// and of a record's SubItem, written back and compared; one that is no number is dropped with a
/// warning.
#[test]
fn units_are_kept() {
    let objects = "<Object><Index>#x8000</Index><Name>Threshold</Name><Type>UDINT</Type>\n\
                   <Info><DefaultData>50c30000</DefaultData><Unit>#xfd260000</Unit></Info></Object>\n\
                   <Object><Index>#x8001</Index><Name>Limits</Name><Type>DT8001</Type><BitSize>48</BitSize>\n\
                   <Info><SubItem><Name>SubIndex 000</Name><Info><DefaultData>01</DefaultData></Info></SubItem>\n\
                   <SubItem><Name>Temperature</Name><Info><DefaultData>5000</DefaultData><Unit>#x2d0000</Unit></Info></SubItem></Info></Object>\n\
                   <Object><Index>#x8002</Index><Name>Odd</Name><Type>UINT</Type><Info><Unit>volts</Unit></Info></Object>";
    let types = "<DataType><Name>DT8001</Name><BitSize>24</BitSize>\
                 <SubItem><SubIdx>0</SubIdx><Name>SubIndex 000</Name><Type>USINT</Type><BitSize>8</BitSize><BitOffs>0</BitOffs></SubItem>\
                 <SubItem><SubIdx>1</SubIdx><Name>Temperature</Name><Type>UINT</Type><BitSize>16</BitSize><BitOffs>8</BitOffs></SubItem>\
                 </DataType>";
    let text =
        device(objects, "").replace("<DataTypes/>", &format!("<DataTypes>{types}</DataTypes>"));
    let (d, findings) = one(&text);
    assert_eq!(
        d.dictionary.entry(0x8000, 0).unwrap().unit,
        Some(0xFD26_0000)
    );
    assert_eq!(d.dictionary.entry(0x8001, 0).unwrap().unit, None);
    assert_eq!(
        d.dictionary.entry(0x8001, 1).unwrap().unit,
        Some(0x002D_0000)
    );
    assert_eq!(d.dictionary.entry(0x8002, 0).unwrap().unit, None);
    assert_eq!(
        said(&findings),
        ["12:75: warning: <Unit> \"volts\" is no 32-bit unit code; the unit is dropped"]
    );
    assert_eq!(od::units::unit_text(0xFD26_0000), "mV");
    // Info only where there is something in it: 0x8000's, 0x8001's and its two SubItems'; none
    // for 0x8002, whose unit was dropped.
    assert_eq!(
        esi::write_all(std::slice::from_ref(&d))
            .matches("<Info")
            .count(),
        4
    );
    // An EDS has no unit: the comparison says what is lost.
    let back = od::eds::read(od::eds::write_eds(&d).as_bytes(), "t.eds").unwrap();
    let lost: Vec<String> = od::diff::diff_devices(&d, &back)
        .iter()
        .map(|x| x.to_string())
        .filter(|x| x.contains("unit"))
        .collect();
    assert_eq!(
        lost,
        [
            "~ 0x8000:00 unit: mV -> none",
            "~ 0x8001:01 unit: °C -> none"
        ]
    );
}

#[test]
fn a_string_shorter_than_its_default_takes_the_default_size() {
    // SOES writes `STRING(0)` for strings set at run time, with the build's default.
    let objects = "<Object><Index>#x1009</Index><Name>Hardware version</Name><Type>STRING(0)</Type><BitSize>0</BitSize>\n\
                   <Info><DefaultString>1.0</DefaultString></Info><Flags><Access>ro</Access></Flags></Object>";
    let (d, findings) = one(&device(objects, ""));
    let e = d.dictionary.entry(0x1009, 0).unwrap();
    assert_eq!(e.data_type, DataType::VisibleString);
    assert_eq!(e.bit_size, Some(24));
    assert_eq!(
        e.default.as_ref().unwrap().value,
        Value::String("1.0".into())
    );
    assert_eq!(
        said(&findings),
        ["8:22: warning: object #x1009: the default takes 24 bits but the type gives 0; the size is the default's"]
    );
}

// ---------------------------------------------------------------------------------------------------------
// Sync managers.

#[test]
fn sm_enable_is_the_number_the_file_gives() {
    // `Enable` is a HexDecValue in the schema: the SII enable byte (9 = enabled, in Op only).
    let sms = "<Sm StartAddress=\"#x1100\" ControlByte=\"#x64\" Enable=\"9\">Outputs</Sm>\n\
               <Sm StartAddress=\"#x1400\" ControlByte=\"#x20\" Enable=\"true\" Virtual=\"true\" OpOnly=\"1\" Watchdog=\"0\">Inputs</Sm>\n\
               <Sm StartAddress=\"#x1800\" ControlByte=\"#x20\" Enable=\"#x0\">Inputs</Sm>\n\
               <Sm StartAddress=\"#x1A00\" ControlByte=\"#x20\" Enable=\"13\" Virtual=\"1\" OpOnly=\"1\">Inputs</Sm>";
    let (d, findings) = one(&device("", sms));
    assert_eq!(findings, vec![]);
    let ecat = d.ethercat.as_ref().unwrap();
    let got: Vec<(u16, u8, bool, bool, bool)> = ecat
        .sync_managers
        .iter()
        .map(|s| {
            (
                s.start_address,
                s.enable,
                s.is_virtual,
                s.op_only,
                s.watchdog,
            )
        })
        .collect();
    assert_eq!(
        got,
        [
            (0x1100, 9, false, false, false),
            (0x1400, 1, true, true, false),
            (0x1800, 0, false, false, false),
            (0x1A00, 13, true, true, false),
        ]
    );
    // The SII SyncM category: 8 bytes per sync manager, the enable byte at 6 (Virtual is bit 2, OpOnly
    // bit 3).
    let image = od::sii::parse(&od::sii::write(&d, 1).unwrap()).unwrap();
    let syncm = image.category(od::sii::category::SYNCM).unwrap();
    // A byte that has the bits already keeps them.
    assert_eq!(
        [syncm[6], syncm[14], syncm[22], syncm[30]],
        [9, 0x0D, 0, 0x0D]
    );

    let e = esi::read_all(
        device("", "<Sm Enable=\"300\">Inputs</Sm>").as_bytes(),
        "t.xml",
    )
    .unwrap_err();
    assert_eq!((e.position.line, e.position.column), (9, 5));
    assert_eq!(
        e.message,
        "expected a number 0..255 in the Enable attribute of <Sm>, found `300`"
    );
}

// ---------------------------------------------------------------------------------------------------------
// PDOs.

#[test]
fn pdo_attributes_are_kept() {
    let pdos = "<TxPdo Sm=\"3\" Su=\"1\" Virtual=\"true\" OSFac=\"10\" OSMin=\"1\" OSMax=\"50\" OSIndexInc=\"1\">\n\
                <Index DependOnSlot=\"true\">#x1A01</Index><Name>Samples</Name>\n\
                <Exclude DependOnSlot=\"1\" DependOnSlotGroup=\"1\">#x1A02</Exclude><Exclude>#x1A03</Exclude>\n\
                <Entry Fixed=\"1\"><Index DependOnSlotGroup=\"true\">#x6002</Index><SubIndex>1</SubIndex><BitLen>16</BitLen>\
                <Name>Value</Name><Comment>first sample</Comment><DataType DScale=\"+/-10\">INT</DataType></Entry>\n\
                </TxPdo>\n\
                <RxPdo Ref=\"DigOutputBit\" Chn=\"1\" Fixed=\"1\" Sm=\"0\"/>";
    let objects = "<Object><Index>#x6002</Index><Name>Samples</Name><Type>DT6002</Type></Object>";
    let text = device(objects, pdos).replace(
        "<DataTypes/>",
        "<DataTypes><DataType><Name>DT6002</Name><BitSize>32</BitSize>\
         <SubItem><SubIdx>0</SubIdx><Name>n</Name><Type>USINT</Type><BitSize>8</BitSize><BitOffs>0</BitOffs></SubItem>\
         <SubItem><SubIdx>1</SubIdx><Name>Value</Name><Type>INT</Type><BitSize>16</BitSize><BitOffs>16</BitOffs>\
         <Flags><Access>ro</Access><PdoMapping>T</PdoMapping></Flags></SubItem></DataType></DataTypes>",
    );
    let (d, findings) = one(&text);
    let ecat = d.ethercat.as_ref().unwrap();
    assert_eq!(
        ecat.rx_pdos,
        vec![],
        "a PDO that only names a template is left out"
    );
    let depend = |slot, slot_group| od::device::SlotDepend { slot, slot_group };
    assert_eq!(
        ecat.tx_pdos,
        [od::device::Pdo {
            index: 0x1A01,
            index_depend: depend(true, false),
            name: "Samples".into(),
            fixed: false,
            mandatory: false,
            is_virtual: true,
            sm: Some(3),
            su: Some(1),
            os_factor: Some(10),
            os_min: Some(1),
            os_max: Some(50),
            os_index_inc: Some(1),
            exclude: vec![
                od::device::PdoRef {
                    index: 0x1A02,
                    depend: depend(true, true)
                },
                0x1A03.into()
            ],
            entries: vec![od::device::PdoEntry {
                index: 0x6002,
                index_depend: depend(false, true),
                sub: 1,
                bit_len: 16,
                name: "Value".into(),
                comment: "first sample".into(),
                data_type: "INT".into(),
                data_scale: "+/-10".into(),
                fixed: true,
            }],
        }]
    );
    assert_eq!(
        said(&findings),
        ["14:1: warning: <RxPdo Ref=\"DigOutputBit\"> refers to a PDO template of the obsolete Descriptions/Pdos list, which is not read; the PDO is left out"]
    );
}

// ---------------------------------------------------------------------------------------------------------
// What the PDOs say about the dictionary.

#[test]
fn entries_missing_from_a_partial_dictionary_are_made_from_the_pdos() {
    let objects = "<Object><Index>#x6000</Index><Name>Status</Name><Type>UINT</Type>\
                   <Flags><Access>ro</Access><PdoMapping>T</PdoMapping></Flags></Object>";
    let pdos = "<TxPdo Sm=\"3\"><Index>#x1A00</Index><Name>Inputs</Name>\n\
<Entry><Index>#x6000</Index><SubIndex>0</SubIndex><BitLen>16</BitLen><Name>Status</Name><DataType>UINT</DataType></Entry>\n\
<Entry><Index>#x6010</Index><SubIndex>1</SubIndex><BitLen>16</BitLen><Name>Value 1</Name><DataType>INT16</DataType></Entry>\n\
<Entry><Index>#x6010</Index><SubIndex>2</SubIndex><BitLen>32</BitLen><Name>Value 2</Name><DataType>UINT32</DataType></Entry>\n\
<Entry><Index>#x6020</Index><SubIndex>0</SubIndex><BitLen>16</BitLen><Name>Bits</Name><DataType>BITARR16</DataType></Entry>\n\
<Entry><Index>#x6030</Index><SubIndex>0</SubIndex><BitLen>12</BitLen><Name>Raw</Name><DataType>FIXED12</DataType></Entry>\n\
<Entry><Index>#x6040</Index><SubIndex>0</SubIndex><BitLen>3</BitLen><Name>Mode</Name></Entry>\n\
<Entry><Index>#x0</Index><BitLen>4</BitLen></Entry>\n\
</TxPdo>\n\
<RxPdo Sm=\"2\"><Index>#x1600</Index><Name>Outputs</Name>\n\
<Entry><Index>#x7000</Index><SubIndex>0</SubIndex><BitLen>8</BitLen><Name>Out</Name><DataType>BYTE</DataType></Entry>\n\
<Entry><Index>#x6010</Index><SubIndex>1</SubIndex><BitLen>16</BitLen><Name>Value 1</Name><DataType>INT16</DataType></Entry>\n\
</RxPdo>";
    let (d, findings) = one(&device(objects, pdos));
    let dict = &d.dictionary;
    assert_eq!(
        dict.objects().map(|o| o.index).collect::<Vec<_>>(),
        [0x6000, 0x6010, 0x6020, 0x6030, 0x6040, 0x7000]
    );
    let record = dict.object(0x6010).unwrap();
    assert_eq!(record.kind, ObjectKind::Record);
    assert_eq!(
        record.name, "Inputs",
        "named after the first PDO that maps it"
    );
    assert_eq!(record.type_name.as_deref(), Some("DT6010"));
    assert_eq!(
        record.subs[&0].default.as_ref().unwrap().value,
        Value::Uint(2)
    );
    let entry = |index, sub| {
        let e = dict.entry(index, sub).unwrap();
        (
            e.name.as_str(),
            e.data_type,
            e.bit_size,
            e.access.kind,
            e.pdo,
        )
    };
    use od::object::{AccessType::Ro, PdoMapping::*};
    assert_eq!(
        entry(0x6010, 1),
        ("Value 1", DataType::Integer16, Some(16), Ro, Both)
    );
    assert_eq!(
        entry(0x6010, 2),
        ("Value 2", DataType::Unsigned32, Some(32), Ro, Tpdo)
    );
    assert_eq!(
        entry(0x6020, 0),
        ("Bits", DataType::Unsigned16, Some(16), Ro, Tpdo)
    );
    assert_eq!(
        entry(0x6030, 0),
        ("Raw", DataType::OctetString, Some(16), Ro, Tpdo)
    );
    assert_eq!(
        entry(0x6040, 0),
        ("Mode", DataType::Bit(3), Some(3), Ro, Tpdo)
    );
    assert_eq!(
        entry(0x7000, 0),
        ("Out", DataType::Unsigned8, Some(8), Ro, Rpdo)
    );
    assert_eq!(dict.entry(0x6010, 1).unwrap().default, Option::None);
    assert_eq!(
        said(&findings),
        [
            "11:1: warning: 0x6010:01: TxPdo #x1A00 maps it, but the dictionary does not have it: made from the PDO (INT, ro, mappable T)",
            "12:1: warning: 0x6010:02: TxPdo #x1A00 maps it, but the dictionary does not have it: made from the PDO (UDINT, ro, mappable T)",
            "13:1: warning: 0x6020:00: TxPdo #x1A00 maps it, but the dictionary does not have it: made from the PDO (UINT, ro, mappable T)",
            "14:1: warning: 0x6030:00: TxPdo #x1A00 gives it the <DataType> `FIXED12`, which names no type: made OCTET_STRING(2) from its BitLen 12",
            "14:1: warning: 0x6030:00: TxPdo #x1A00 maps it, but the dictionary does not have it: made from the PDO (OCTET_STRING(2), ro, mappable T)",
            "15:1: warning: 0x6040:00: TxPdo #x1A00 gives it no <DataType>: made BIT3 from its BitLen 3",
            "15:1: warning: 0x6040:00: TxPdo #x1A00 maps it, but the dictionary does not have it: made from the PDO (BIT3, ro, mappable T)",
            "19:1: warning: 0x7000:00: RxPdo #x1600 maps it, but the dictionary does not have it: made from the PDO (USINT, ro, mappable R)",
        ]
    );
    // The PDOs keep the type names as the file spells them.
    let tx = &d.ethercat.as_ref().unwrap().tx_pdos[0];
    assert_eq!(tx.entries[1].data_type, "INT16");
    assert_eq!(tx.entries[3].data_type, "BITARR16");
    // Nothing is left for validate to say about the mapping.
    assert_eq!(od::validate::validate(&d), vec![]);
}

#[test]
fn a_device_without_a_dictionary_gets_one_from_its_pdos() {
    let text = "<?xml version=\"1.0\"?>\n<EtherCATInfo><Vendor><Id>2</Id><Name>V</Name></Vendor>\n\
<Descriptions><Groups/><Devices><Device>\n<Type ProductCode=\"#x10\" RevisionNo=\"1\">EK1</Type><Name>Coupler</Name>\n\
<TxPdo Fixed=\"1\" Sm=\"3\"><Index>#x1A00</Index><Name>ID</Name>\n\
<Entry><Index>#x6000</Index><SubIndex>1</SubIndex><BitLen>8</BitLen><Name>ID</Name><DataType>UINT8</DataType></Entry>\n\
<Entry><Index>#x6000</Index><SubIndex>2</SubIndex><BitLen>24</BitLen><Name>Serial</Name><DataType>T_SERIAL</DataType></Entry>\n\
<Entry><Index>#x6001</Index><SubIndex>0</SubIndex><BitLen>1</BitLen><Name>Ok</Name><DataType>BOOL</DataType></Entry>\n\
</TxPdo>\n</Device></Devices></Descriptions></EtherCATInfo>\n";
    let (d, findings) = one(text);
    let dict = &d.dictionary;
    assert_eq!(dict.len(), 2);
    assert_eq!(dict.object(0x6000).unwrap().kind, ObjectKind::Record);
    let t = |i, s| dict.entry(i, s).unwrap().data_type;
    assert_eq!(
        [t(0x6000, 0), t(0x6000, 1), t(0x6000, 2), t(0x6001, 0)],
        [
            DataType::Unsigned8,
            DataType::Unsigned8,
            DataType::Unsigned24,
            DataType::Boolean
        ]
    );
    // Without a dictionary the made entries are no news; a type without a name is.
    assert_eq!(
        said(&findings),
        ["7:1: warning: 0x6000:02: TxPdo #x1A00 gives it the <DataType> `T_SERIAL`, which names no type: made UINT24 from its BitLen 24"]
    );
    // Without CoE there is no object dictionary to have mandatory objects; with CoE and no dictionary
    // in the file (SOES's RTL_ATO.xml), the master reads it by SDO Information; with CoE and
    // communication objects in the file, 0x1000 and 0x1018 are missing.
    assert_eq!(od::validate::validate(&d), vec![]);
    let coe = text.replace(
        "</TxPdo>",
        "</TxPdo>\n<Mailbox><CoE SdoInfo=\"1\"/></Mailbox>",
    );
    let (d, _) = one(&coe);
    assert_eq!(od::validate::validate(&d), vec![]);
    let coe = coe.replace(
        "<TxPdo Fixed",
        "<Profile><Dictionary><Objects><Object><Index>#x1008</Index><Name>Device name</Name>\
         <Type>STRING(4)</Type><BitSize>32</BitSize></Object></Objects></Dictionary></Profile>\n<TxPdo Fixed",
    );
    let (d, _) = one(&coe);
    let found: Vec<String> = od::validate::validate(&d)
        .iter()
        .map(|f| f.to_string())
        .collect();
    assert_eq!(
        found,
        [
            "warning: object 0x1000 (device type) is mandatory and missing",
            "warning: object 0x1018 (identity) is mandatory and missing",
        ]
    );
}

#[test]
fn the_pdos_win_over_a_missing_or_other_pdo_mapping() {
    let types = "<DataTypes><DataType><Name>DT8000ARR</Name><BaseType>UINT</BaseType><BitSize>32</BitSize>\
                 <ArrayInfo><LBound>1</LBound><Elements>2</Elements></ArrayInfo></DataType>\
                 <DataType><Name>DT8000</Name><BitSize>48</BitSize>\
                 <SubItem><SubIdx>0</SubIdx><Name>n</Name><Type>USINT</Type><BitSize>8</BitSize><BitOffs>0</BitOffs></SubItem>\
                 <SubItem><Name>Elements</Name><Type>DT8000ARR</Type><BitSize>32</BitSize><BitOffs>16</BitOffs>\
                 <Flags><Access>ro</Access></Flags></SubItem></DataType></DataTypes>";
    let objects = "<Object><Index>#x6000</Index><Name>A</Name><Type>UINT</Type><Flags><Access>ro</Access></Flags></Object>\n\
<Object><Index>#x7000</Index><Name>B</Name><Type>UINT</Type><Flags><Access>rw</Access><PdoMapping>T</PdoMapping></Flags></Object>\n\
<Object><Index>#x8000</Index><Name>C</Name><Type>DT8000</Type><Info><SubItem><Name>n</Name><Info><DefaultData>02</DefaultData></Info></SubItem></Info></Object>\n\
<Object><Index>#x6001</Index><Name>D</Name><Type>UINT</Type><Flags><Access>ro</Access><PdoMapping>t</PdoMapping></Flags></Object>";
    let pdos = "<TxPdo Sm=\"3\"><Index>#x1A00</Index><Name>In</Name>\n\
<Entry><Index>#x6000</Index><SubIndex>0</SubIndex><BitLen>16</BitLen><Name>A</Name><DataType>UINT</DataType></Entry>\n\
<Entry><Index>#x8000</Index><SubIndex>2</SubIndex><BitLen>16</BitLen><Name>C2</Name><DataType>UINT</DataType></Entry>\n\
<Entry><Index>#x6001</Index><SubIndex>0</SubIndex><BitLen>16</BitLen><Name>D</Name><DataType>UINT</DataType></Entry>\n\
</TxPdo>\n\
<RxPdo Fixed=\"1\" Sm=\"2\"><Index>#x1600</Index><Name>Out</Name>\n\
<Entry><Index>#x7000</Index><SubIndex>0</SubIndex><BitLen>16</BitLen><Name>B</Name><DataType>UINT</DataType></Entry>\n\
</RxPdo>";
    let text = device(objects, pdos).replace("<DataTypes/>", types);
    let (d, findings) = one(&text);
    let pdo = |i, s| d.dictionary.entry(i, s).unwrap().pdo;
    use od::object::PdoMapping::{self, *};
    assert_eq!(pdo(0x6000, 0), Tpdo);
    assert_eq!(pdo(0x7000, 0), Both);
    assert_eq!(pdo(0x6001, 0), Tpdo);
    assert_eq!(
        [pdo(0x8000, 0), pdo(0x8000, 1), pdo(0x8000, 2)],
        [PdoMapping::None, Tpdo, Tpdo],
        "the elements of an array share one PdoMapping"
    );
    assert_eq!(d.dictionary.object(0x8000).unwrap().kind, ObjectKind::Array);
    assert_eq!(
        said(&findings),
        [
            "13:1: warning: 0x6000:00: TxPdo #x1A00 maps it, but its <PdoMapping> is missing: read as T",
            "14:1: warning: 0x8000:02: TxPdo #x1A00 maps it, but its <PdoMapping> is missing: read as T",
            "18:1: warning: 0x7000:00: RxPdo #x1600 maps it, but its <PdoMapping> says T: read as RT",
        ]
    );
    assert_eq!(od::validate::validate(&d), vec![]);
}

#[test]
fn one_entry_mapped_with_different_lengths() {
    // Virtual PDOs map windows of ESC registers (0x1D09:B0 = the latch time registers from 0x09B0) with
    // 32 or 64 bits: any length is a reading that fits. Two plain PDOs that map one entry with
    // different lengths are a contradiction, which validate names.
    let text = "<?xml version=\"1.0\"?>\n<EtherCATInfo><Vendor><Id>2</Id><Name>V</Name></Vendor>\n\
<Descriptions><Groups/><Devices><Device>\n<Type ProductCode=\"#x10\" RevisionNo=\"1\">ER1</Type><Name>Latch</Name>\n\
<TxPdo Virtual=\"true\" Sm=\"3\"><Index>#x1A12</Index><Name>Latch 32</Name>\n\
<Entry><Index>#x1D09</Index><SubIndex>#xB0</SubIndex><BitLen>32</BitLen><Name>LatchPos0</Name><DataType>UDINT</DataType></Entry>\n\
</TxPdo>\n\
<TxPdo Virtual=\"true\" Sm=\"3\"><Index>#x1A13</Index><Name>Latch 64</Name>\n\
<Entry><Index>#x1D09</Index><SubIndex>#xB0</SubIndex><BitLen>64</BitLen><Name>LatchPos0</Name><DataType>ULINT</DataType></Entry>\n\
</TxPdo>\n\
<RxPdo Sm=\"2\"><Index>#x1600</Index><Name>Byte</Name>\n\
<Entry><Index>#x7000</Index><SubIndex>0</SubIndex><BitLen>8</BitLen><Name>Out</Name><DataType>USINT</DataType></Entry>\n\
</RxPdo>\n\
<RxPdo Sm=\"2\"><Index>#x1601</Index><Name>Word</Name>\n\
<Entry><Index>#x7000</Index><SubIndex>0</SubIndex><BitLen>16</BitLen><Name>Out</Name><DataType>UINT</DataType></Entry>\n\
</RxPdo>\n</Device></Devices></Descriptions></EtherCATInfo>\n";
    let reading = read(text);
    assert_eq!(reading.findings, vec![]);
    let d = &reading.devices[0];
    let latch = d.dictionary.entry(0x1D09, 0xB0).unwrap();
    assert_eq!(
        latch.data_type,
        DataType::Unsigned32,
        "the first PDO that maps it"
    );
    assert_eq!(
        d.dictionary.entry(0x7000, 0).unwrap().data_type,
        DataType::Unsigned8
    );
    let found = od::validate::validate_mapped(d, &reading.sources[0]);
    assert_eq!(
        said(&found),
        ["15:1: warning: 0x1601:00: maps 0x7000:00 with 16 bits, its type UNSIGNED8 has 8"]
    );
}

// ---------------------------------------------------------------------------------------------------------
// Gaps, DS301-era objects, NaN defaults, counts.

#[test]
fn gaps_of_any_length_survive_writing_and_the_sii_image() {
    // Index 0 is a gap of BitLen bits (ETG.1000.6), in a PDO and in a mapping object's entries.
    let objects = "<Object><Index>#x6000</Index><Name>A</Name><Type>UINT</Type><Flags><Access>ro</Access><PdoMapping>T</PdoMapping></Flags></Object>\n\
<Object><Index>#x1A00</Index><Name>In</Name><Type>DT1A00</Type><Info>\
<SubItem><Name>n</Name><Info><DefaultData>03</DefaultData></Info></SubItem>\
<SubItem><Name>1</Name><Info><DefaultData>10000060</DefaultData></Info></SubItem>\
<SubItem><Name>2</Name><Info><DefaultData>0D000000</DefaultData></Info></SubItem>\
<SubItem><Name>3</Name><Info><DefaultData>10000000</DefaultData></Info></SubItem></Info></Object>";
    let types = "<DataTypes><DataType><Name>DT1A00</Name><BitSize>112</BitSize>\
<SubItem><SubIdx>0</SubIdx><Name>n</Name><Type>USINT</Type><BitSize>8</BitSize><BitOffs>0</BitOffs></SubItem>\
<SubItem><SubIdx>1</SubIdx><Name>1</Name><Type>UDINT</Type><BitSize>32</BitSize><BitOffs>16</BitOffs></SubItem>\
<SubItem><SubIdx>2</SubIdx><Name>2</Name><Type>UDINT</Type><BitSize>32</BitSize><BitOffs>48</BitOffs></SubItem>\
<SubItem><SubIdx>3</SubIdx><Name>3</Name><Type>UDINT</Type><BitSize>32</BitSize><BitOffs>80</BitOffs></SubItem>\
</DataType></DataTypes>";
    let pdos = "<TxPdo Fixed=\"1\" Sm=\"3\"><Index>#x1A00</Index><Name>In</Name>\n\
<Entry><Index>#x6000</Index><SubIndex>0</SubIndex><BitLen>16</BitLen><Name>A</Name><DataType>UINT</DataType></Entry>\n\
<Entry><Index>#x0</Index><BitLen>13</BitLen></Entry>\n\
<Entry><Index>0</Index><SubIndex>0</SubIndex><BitLen>300</BitLen><Name>Reserved</Name></Entry>\n\
<Entry><Index>#x0</Index><BitLen>16</BitLen></Entry>\n\
</TxPdo>";
    let text = device(objects, pdos).replace("<DataTypes/>", types);
    let (d, findings) = one(&text);
    assert_eq!(findings, vec![]);
    let tx = &d.ethercat.as_ref().unwrap().tx_pdos[0];
    let gaps: Vec<(u16, u8, u16, &str)> = tx.entries[1..]
        .iter()
        .map(|e| (e.index, e.sub, e.bit_len, e.name.as_str()))
        .collect();
    assert_eq!(
        gaps,
        [(0, 0, 13, ""), (0, 0, 300, "Reserved"), (0, 0, 16, "")]
    );
    assert_eq!(
        od::validate::validate(&d),
        vec![],
        "gaps are no missing objects"
    );
    // The SII TxPDO category: 8 bytes of PDO header, then 8 bytes per entry with the bit length in its
    // byte 5; the 300-bit gap is two entries (255 + 45 bits).
    let image = od::sii::parse(&od::sii::write(&d, 1).unwrap()).unwrap();
    let tx = image.category(od::sii::category::TXPDO).unwrap();
    assert_eq!(tx[2], 5, "entries");
    let entries: Vec<(u16, u8)> = tx[8..]
        .chunks(8)
        .map(|e| (u16::from_le_bytes([e[0], e[1]]), e[5]))
        .collect();
    assert_eq!(entries, [(0x6000, 16), (0, 13), (0, 255), (0, 45), (0, 16)]);
}

#[test]
fn ds301_number_of_pdos_supported() {
    // DS301 v4.0's 0x1004: an ARRAY whose sub-index 0 is an UNSIGNED32 (RxPDOs in the low word, TxPDOs
    // in the high word), then the synchronous and asynchronous PDOs; Beckhoff AX2000 files still have it.
    let types = "<DataTypes><DataType><Name>DT1004ARR</Name><BaseType>UDINT</BaseType><BitSize>64</BitSize>\
<ArrayInfo><LBound>1</LBound><Elements>2</Elements></ArrayInfo></DataType>\
<DataType><Name>DT1004</Name><BitSize>80</BitSize>\
<SubItem><SubIdx>0</SubIdx><Name>Number of RxPDOs/TxPDOs</Name><Type>UDINT</Type><BitSize>32</BitSize><BitOffs>0</BitOffs></SubItem>\
<SubItem><Name>Elements</Name><Type>DT1004ARR</Type><BitSize>64</BitSize><BitOffs>16</BitOffs><Flags><Access>rw</Access></Flags></SubItem>\
</DataType></DataTypes>";
    let objects = "<Object><Index>#x1004</Index><Name>Number of PDOs supported</Name><Type>DT1004</Type><BitSize>80</BitSize><Info>\
<SubItem><Name>Number of RxPDOs/TxPDOs</Name><Info><DefaultData>03000300</DefaultData></Info></SubItem>\
<SubItem><Name>SubIndex 001</Name><Info><DefaultData>00000000</DefaultData></Info></SubItem>\
<SubItem><Name>SubIndex 002</Name><Info><DefaultData>03000300</DefaultData></Info></SubItem>\
</Info><Flags><Access>rw</Access></Flags></Object>";
    let text = device(objects, "").replace("<DataTypes/>", types);
    let (d, findings) = one(&text);
    assert_eq!(findings, vec![]);
    let o = d.dictionary.object(0x1004).unwrap();
    assert_eq!(o.kind, ObjectKind::Array);
    assert_eq!(o.subs.len(), 3);
    let zero = &o.subs[&0];
    assert_eq!(
        (zero.name.as_str(), zero.data_type),
        ("Number of RxPDOs/TxPDOs", DataType::Unsigned32)
    );
    assert_eq!(
        zero.default.as_ref().unwrap().value,
        Value::Uint(0x0003_0003)
    );
    assert_eq!(
        o.subs[&2].default.as_ref().unwrap().value,
        Value::Uint(0x0003_0003)
    );
    assert_eq!(o.subs[&1].access.kind, od::object::AccessType::Rw);
    assert_eq!(
        od::validate::validate(&d),
        vec![],
        "the DS301 form of 0x1004 is no fault"
    );
    // The writer puts the elements after the 32-bit sub-index 0.
    let written = esi::write(&d);
    let flat: String = written.lines().map(str::trim).collect();
    assert!(
        flat.contains("<Name>DT1004</Name><BitSize>96</BitSize>"),
        "{written}"
    );
    assert!(
        flat.contains(
            "<Name>Elements</Name><Type>DT1004ARR</Type><BitSize>64</BitSize><BitOffs>32</BitOffs>"
        ),
        "{written}"
    );
}

#[test]
fn nan_defaults_keep_their_bits() {
    // C4FFFFFF is a REAL NaN (a vendor's -60 as a DINT in a REAL object); an LREAL NaN with a payload.
    let objects = "<Object><Index>#x2503</Index><Name>Min out</Name><Type>REAL</Type><BitSize>32</BitSize>\
<Info><DefaultData>c4ffffff</DefaultData></Info><Flags><Access>rw</Access></Flags></Object>\n\
<Object><Index>#x2504</Index><Name>Gain</Name><Type>LREAL</Type><BitSize>64</BitSize>\
<Info><DefaultData>01000000A0FFF87F</DefaultData></Info><Flags><Access>rw</Access></Flags></Object>";
    let (d, findings) = one(&device(objects, ""));
    assert_eq!(findings, vec![]);
    let bits32 = match d
        .dictionary
        .entry(0x2503, 0)
        .unwrap()
        .default
        .as_ref()
        .unwrap()
        .value
    {
        Value::Real32(v) => v.to_bits(),
        ref other => panic!("{other:?}"),
    };
    let bits64 = match d
        .dictionary
        .entry(0x2504, 0)
        .unwrap()
        .default
        .as_ref()
        .unwrap()
        .value
    {
        Value::Real64(v) => v.to_bits(),
        ref other => panic!("{other:?}"),
    };
    assert_eq!((bits32, bits64), (0xFFFF_FFC4, 0x7FF8_FFA0_0000_0001));
    let written = esi::write(&d);
    assert!(
        written.contains("<DefaultData>C4FFFFFF</DefaultData>"),
        "{written}"
    );
    assert!(
        written.contains("<DefaultData>01000000A0FFF87F</DefaultData>"),
        "{written}"
    );
    let back = esi::read(written.as_bytes(), "w.xml", None).unwrap();
    assert_eq!(
        back.dictionary.entry(0x2504, 0).unwrap().value,
        [1, 0, 0, 0, 0xA0, 0xFF, 0xF8, 0x7F]
    );
}

#[test]
fn only_a_count_the_file_gives_is_checked() {
    // A RECORD whose sub-index 0 has no default says nothing about its count; one that says 1 with two
    // entries is wrong; a mapping object that maps one of its two entries is right.
    let types = "<DataTypes><DataType><Name>DT2000</Name><BitSize>48</BitSize>\
<SubItem><SubIdx>0</SubIdx><Name>n</Name><Type>USINT</Type><BitSize>8</BitSize><BitOffs>0</BitOffs></SubItem>\
<SubItem><SubIdx>1</SubIdx><Name>a</Name><Type>UINT</Type><BitSize>16</BitSize><BitOffs>16</BitOffs></SubItem>\
<SubItem><SubIdx>2</SubIdx><Name>b</Name><Type>UINT</Type><BitSize>16</BitSize><BitOffs>32</BitOffs></SubItem>\
</DataType></DataTypes>";
    let objects = "<Object><Index>#x2000</Index><Name>No count</Name><Type>DT2000</Type></Object>\n\
<Object><Index>#x2001</Index><Name>Short count</Name><Type>DT2000</Type><Info><SubItem><Name>n</Name><Info><DefaultData>01</DefaultData></Info></SubItem></Info></Object>\n\
<Object><Index>#x1A00</Index><Name>Mapping</Name><Type>DT2000</Type><Info><SubItem><Name>n</Name><Info><DefaultData>01</DefaultData></Info></SubItem></Info></Object>";
    let reading = read(&device(objects, "").replace("<DataTypes/>", types));
    let found = od::validate::validate_mapped(&reading.devices[0], &reading.sources[0]);
    assert_eq!(
        said(&found),
        ["8:79: warning: 0x2001:00: sub-index 0 says 1 but the highest sub-index is 2"],
        "at the entry's Info/SubItem"
    );
}

// ---------------------------------------------------------------------------------------------------------
// Modular devices (ETG.2001): slots and modules.

const MODULAR: &str = r##"<?xml version="1.0"?>
<EtherCATInfo>
<Vendor><Id>#xE0000001</Id><Name>V</Name></Vendor>
<Descriptions><Groups/><Devices>
<Device>
<Type ProductCode="#x10000" RevisionNo="1">Drive1</Type><Name LcId="1031">Antrieb</Name><Name LcId="1033">Drive</Name>
<Mailbox><CoE SdoInfo="1"><InitCmd Fixed="1"><Transition>PS</Transition><Transition>SO</Transition><Index>#x6060</Index><SubIndex>0</SubIndex><Data>08</Data><Comment>csp</Comment></InitCmd></CoE></Mailbox>
<Slots SlotPdoIncrement="16" SlotIndexIncrement="#x800" MaxSlotCount="2" DownloadModuleIdentList="1" IdentifyModuleBy="ModuleIdent">
<Slot MinInstances="1" MaxInstances="1" SlotGroup="1" TreeView="SLOT"><Name LcId="1031">Achse 1</Name><Name LcId="1033">Axis 1</Name>
<ModuleIdent Default="1">#x100</ModuleIdent><ModuleIdent>#x101</ModuleIdent></Slot>
<Slot MinInstances="0" MaxInstances="32" SlotIndexIncrement="#x10"><Name>Terminals</Name>
<ModuleClass><Class>DI</Class><VendorId>#xE0000001</VendorId><Name LcId="1033">Digital inputs</Name><ImageData16x14>00</ImageData16x14></ModuleClass></Slot>
<ModulePdoGroup Alignment="2" RxPdo="#x1600" TxPdo="#x1A00">Digital</ModulePdoGroup>
</Slots>
</Device>
<Device>
<Type ProductCode="#x10001" RevisionNo="1">Drive2</Type><Name>Drive 2</Name>
</Device>
</Devices>
<Modules>
<Module>
<Type ModuleIdent="#x0100" ModuleClass="DI" ModulePdoGroup="1">Position Mode</Type>
<Name>Position Mode; synchronous with process data</Name>
<RxPdo Fixed="true" Sm="2"><Index DependOnSlot="true">#x1600</Index><Name>Position Outputs</Name>
<Entry><Index DependOnSlot="true">#x607A</Index><SubIndex>0</SubIndex><BitLen>32</BitLen><Name>TargetPosition</Name><DataType>DINT</DataType></Entry>
</RxPdo>
<Mailbox><CoE CompleteAccess="true"><InitCmd><Transition>PS</Transition><Index DependOnSlot="true">#x8000</Index><SubIndex>1</SubIndex><Data AdaptAutomatically="1">0A00</Data></InitCmd></CoE></Mailbox>
<Profile><ProfileNo>402</ProfileNo><AddInfo>2</AddInfo><Dictionary><DataTypes/><Objects>
<Object><Index>#x8000</Index><Name>Setting</Name><Type>UINT</Type><Info><DefaultValue>10</DefaultValue></Info><Flags><Access>rw</Access></Flags></Object>
</Objects></Dictionary></Profile>
<DcOpModeName>Synchron</DcOpModeName>
</Module>
<Module>
<Type ModuleIdent="#x0101">Position Mode (DC)</Type>
<Name>Position Mode; DC</Name>
<TxPdo Fixed="true" Sm="3"><Index DependOnSlot="true">#x1A00</Index><Name>Position Inputs</Name>
<Entry><Index DependOnSlot="true">#x6064</Index><SubIndex>0</SubIndex><BitLen>32</BitLen><Name>ActualPosition</Name><DataType>DINT</DataType></Entry>
</TxPdo>
<Profile><ProfileNo>402</ProfileNo></Profile>
</Module>
</Modules>
</Descriptions>
</EtherCATInfo>
"##;

#[test]
fn slots_and_modules_of_a_modular_device() {
    use od::device::{InitCmd, ModulePdoGroup, Slot, SlotModuleClass, SlotModuleIdent, Slots};
    let reading = read(MODULAR);
    assert_eq!(reading.devices.len(), 2, "modules are not devices");
    // The first module's PDO maps 0x607A, which its dictionary lacks.
    assert_eq!(
        said(&reading.findings),
        ["25:1: warning: 0x607A:00: RxPdo #x1600 maps it, but the dictionary does not have it: made from the PDO (DINT, ro, mappable R)"]
    );
    let (first, second) = (
        reading.devices[0].ethercat.as_ref().unwrap(),
        reading.devices[1].ethercat.as_ref().unwrap(),
    );
    assert!(
        std::sync::Arc::ptr_eq(&first.modules, &second.modules),
        "the devices of a file share its modules"
    );
    assert_eq!(
        first.slots,
        Some(Slots {
            max_slot_count: Some(2),
            max_slot_group_count: None,
            slot_pdo_increment: Some(16),
            slot_group_pdo_increment: None,
            slot_index_increment: Some(0x800),
            slot_group_index_increment: None,
            download_module_ident_list: true,
            identify_module_by: "ModuleIdent".into(),
            slots: vec![
                Slot {
                    name: "Axis 1".into(),
                    slot_group: Some(1),
                    min_instances: 1,
                    max_instances: 1,
                    tree_view: "SLOT".into(),
                    module_idents: vec![
                        SlotModuleIdent {
                            ident: 0x100,
                            default: Some(1)
                        },
                        SlotModuleIdent {
                            ident: 0x101,
                            default: None
                        },
                    ],
                    ..Slot::default()
                },
                Slot {
                    name: "Terminals".into(),
                    min_instances: 0,
                    max_instances: 32,
                    slot_index_increment: Some(0x10),
                    module_classes: vec![SlotModuleClass {
                        class: "DI".into(),
                        vendor_id: Some(0xE000_0001),
                        name: "Digital inputs".into(),
                    }],
                    ..Slot::default()
                },
            ],
            module_pdo_groups: vec![ModulePdoGroup {
                name: "Digital".into(),
                alignment: Some(2),
                rx_pdo: Some(0x1600),
                tx_pdo: Some(0x1A00),
            }],
        })
    );
    assert_eq!(second.slots, None);
    assert_eq!(
        first.mailbox.as_ref().unwrap().init_cmds,
        [InitCmd {
            transitions: vec!["PS".into(), "SO".into()],
            index: 0x6060,
            sub: 0,
            data: vec![8],
            comment: "csp".into(),
            fixed: true,
            ..InitCmd::default()
        }]
    );
}

#[test]
fn modules_of_a_modular_device_with_their_parts() {
    use od::device::{InitCmd, SlotDepend};
    let reading = read(MODULAR);
    let first = reading.devices[0].ethercat.as_ref().unwrap();
    let modules = &first.modules;
    assert_eq!(modules.len(), 2);
    let m = &modules[0];
    assert_eq!(
        (
            m.ident,
            m.class.as_str(),
            m.pdo_group,
            m.type_name.as_str(),
            m.name.as_str()
        ),
        (
            0x100,
            "DI",
            Some(1),
            "Position Mode",
            "Position Mode; synchronous with process data"
        )
    );
    assert_eq!(
        (m.profile_no, m.add_info, m.dc_op_mode_name.as_str()),
        (Some(402), Some(2), "Synchron")
    );
    let slot = SlotDepend {
        slot: true,
        slot_group: false,
    };
    assert_eq!(m.rx_pdos[0].index, 0x1600);
    assert_eq!(m.rx_pdos[0].index_depend, slot);
    assert_eq!(m.rx_pdos[0].entries[0].index_depend, slot);
    assert_eq!(m.tx_pdos, vec![]);
    let mb = m.mailbox.as_ref().unwrap();
    assert!(mb.coe.unwrap().complete_access);
    assert_eq!(
        mb.init_cmds,
        [InitCmd {
            transitions: vec!["PS".into()],
            index: 0x8000,
            index_depend: slot,
            sub: 1,
            data: vec![0x0A, 0],
            adapt_automatically: true,
            ..InitCmd::default()
        }]
    );
    assert_eq!(
        m.dictionary.objects().map(|o| o.index).collect::<Vec<_>>(),
        [0x607A, 0x8000]
    );
    assert_eq!(
        m.dictionary
            .entry(0x8000, 0)
            .unwrap()
            .default
            .as_ref()
            .unwrap()
            .value,
        Value::Uint(10)
    );
    // A module without a dictionary gets one from its PDOs, as a device does (no news).
    let m = &modules[1];
    assert_eq!((m.ident, m.class.as_str(), m.pdo_group), (0x101, "", None));
    assert_eq!(
        (m.profile_no, m.add_info, m.mailbox.is_none()),
        (Some(402), None, true)
    );
    assert_eq!(
        m.dictionary.entry(0x6064, 0).unwrap().data_type,
        DataType::Integer32
    );
    // Written once for both devices.
    let written = esi::write_all(&reading.devices);
    assert_eq!(written.matches("<Module>").count(), 2, "{written}");
    assert_eq!(written.matches("<Modules>").count(), 1);
}

#[test]
fn modules_written_together_are_written_once() {
    // A file's own duplicate module stays; descriptions from two readings share their modules when
    // written together.
    let module =
        &MODULAR[MODULAR.find("<Module>").unwrap()..MODULAR.find("</Module>").unwrap() + 9];
    let twice = MODULAR.replace(module, &format!("{module}\n{module}"));
    let reading = read(&twice);
    assert_eq!(
        reading.devices[0].ethercat.as_ref().unwrap().modules.len(),
        3
    );
    let other = esi::read_all(MODULAR.as_bytes(), "other.xml").unwrap();
    let mut both = reading.devices.clone();
    both.push(other[0].clone());
    let back = esi::read_all(esi::write_all(&both).as_bytes(), "w.xml").unwrap();
    let modules = &back[2].ethercat.as_ref().unwrap().modules;
    assert_eq!(
        modules.len(),
        3,
        "the second file's modules are the first's"
    );
}

#[test]
fn what_a_template_pdo_holds_is_left_out_with_it() {
    // A PDO that refers to a template and still has children: they belong to it, not to the PDO before.
    let pdos = "<RxPdo Sm=\"2\"><Index>#x1600</Index><Name>Out</Name>\n\
<Entry><Index>#x0</Index><BitLen>8</BitLen></Entry></RxPdo>\n\
<RxPdo Ref=\"DigOutputBit\" Sm=\"2\"><Index>#x1601</Index><Name>Ref</Name><Exclude>#x1600</Exclude>\n\
<Entry><Index>#x0</Index><BitLen>16</BitLen></Entry></RxPdo>";
    let (d, findings) = one(&device("", pdos));
    let rx = &d.ethercat.as_ref().unwrap().rx_pdos;
    assert_eq!(rx.len(), 1);
    assert_eq!(
        (
            rx[0].index,
            rx[0].name.as_str(),
            rx[0].exclude.len(),
            rx[0].entries.len()
        ),
        (0x1600, "Out", 0, 1)
    );
    assert_eq!(findings.len(), 1);
}

#[test]
fn a_profile_number_is_kept_for_modules_only() {
    // A device's ProfileNo is not kept, so it is not read; a module's is, and one that is no number is
    // left out with a warning.
    let text = MODULAR
        .replace(
            "<Name LcId=\"1033\">Drive</Name>",
            "<Name LcId=\"1033\">Drive</Name><Profile><ProfileNo>DS402</ProfileNo></Profile>",
        )
        .replace(
            "<ProfileNo>402</ProfileNo><AddInfo>2</AddInfo>",
            "<ProfileNo>402</ProfileNo><AddInfo>two</AddInfo>",
        );
    let reading = read(&text);
    let module = &reading.devices[0].ethercat.as_ref().unwrap().modules[0];
    assert_eq!((module.profile_no, module.add_info), (Some(402), None));
    assert_eq!(
        said(&reading.findings)[0],
        "25:1: warning: 0x607A:00: RxPdo #x1600 maps it, but the dictionary does not have it: made from the PDO (DINT, ro, mappable R)"
    );
    assert_eq!(
        said(&reading.findings)[1],
        "28:45: warning: expected a number like #x1A00 or 6656 in <Profile>/<AddInfo>, found `two`; it is left out"
    );
    assert_eq!(reading.findings.len(), 2);
}

/// A PDO entry at 0x0001–0x0007 is a CiA 301 dummy entry (KickCAT's examples map 0x0006:01, an
/// UNSIGNED16's worth): padding, not an object the dictionary is to get from the PDO.
#[test]
fn dummy_entries_are_padding() {
    let objects = "<Object><Index>#x6000</Index><Name>A</Name><Type>UINT</Type><Flags><Access>ro</Access><PdoMapping>T</PdoMapping></Flags></Object>";
    let pdos = "<TxPdo Fixed=\"1\" Sm=\"3\"><Index>#x1A00</Index><Name>In</Name>\n\
<Entry><Index>#x6000</Index><SubIndex>0</SubIndex><BitLen>16</BitLen><Name>A</Name><DataType>UINT</DataType></Entry>\n\
<Entry><Index>#x0006</Index><SubIndex>1</SubIndex><BitLen>16</BitLen><Name>pad</Name><DataType>UINT</DataType></Entry>\n\
<Entry><Index>#x0007</Index><SubIndex>0</SubIndex><BitLen>32</BitLen><DataType>UDINT</DataType></Entry>\n\
<Entry><Index>#x0008</Index><SubIndex>0</SubIndex><BitLen>8</BitLen><Name>b</Name><DataType>USINT</DataType></Entry>\n\
</TxPdo>";
    let (d, findings) = one(&device(objects, pdos));
    let indices: Vec<u16> = d.dictionary.objects().map(|o| o.index).collect();
    assert_eq!(
        indices,
        [0x0008, 0x6000],
        "0x0008 is no dummy: made from the PDO"
    );
    assert_eq!(findings.len(), 1, "{:?}", said(&findings));
    assert!(
        said(&findings)[0].contains("0x0008:00"),
        "{:?}",
        said(&findings)
    );
    let tx = &d.ethercat.as_ref().unwrap().tx_pdos[0];
    assert_eq!(tx.entries.len(), 4);
    assert_eq!(od::validate::validate(&d), vec![]);
}

/// The SII entry of a PDO entry carries the CoE data type index: ETG.1000.6's bit arrays BITARR8, 16 and
/// 32 have 0x2D, 0x2E and 0x2F; other types their CiA 301 index (UINT 0x0006), an unknown name 0.
#[test]
fn bit_arrays_have_their_own_sii_type_index() {
    let pdos = "<TxPdo Fixed=\"1\" Sm=\"3\"><Index>#x1A00</Index><Name>In</Name>\n\
<Entry><Index>#x6000</Index><SubIndex>1</SubIndex><BitLen>8</BitLen><Name>a</Name><DataType>BITARR8</DataType></Entry>\n\
<Entry><Index>#x6000</Index><SubIndex>2</SubIndex><BitLen>16</BitLen><Name>b</Name><DataType>bitarr16</DataType></Entry>\n\
<Entry><Index>#x6000</Index><SubIndex>3</SubIndex><BitLen>32</BitLen><Name>c</Name><DataType>BITARR32</DataType></Entry>\n\
<Entry><Index>#x6000</Index><SubIndex>4</SubIndex><BitLen>16</BitLen><Name>d</Name><DataType>UINT</DataType></Entry>\n\
<Entry><Index>#x6000</Index><SubIndex>5</SubIndex><BitLen>16</BitLen><Name>e</Name><DataType>T_OWN</DataType></Entry>\n\
</TxPdo>";
    let (d, _) = one(&device("", pdos));
    let image = od::sii::parse(&od::sii::write(&d, 1).unwrap()).unwrap();
    let tx = image.category(od::sii::category::TXPDO).unwrap();
    // 8 bytes of PDO header, then 8 bytes per entry: index (2), sub-index, name, data type, bit length.
    let types: Vec<(u8, u8)> = tx[8..].chunks(8).map(|e| (e[2], e[4])).collect();
    assert_eq!(
        types,
        [(1, 0x2D), (2, 0x2E), (3, 0x2F), (4, 0x06), (5, 0x00)]
    );
}

/// A PDO entry's bit length in the SII is one byte: a gap longer than 255 bits becomes several gaps, an
/// entry of an object that long (an OCTET_STRING of 40 bytes) stays one entry, at 255.
#[test]
fn only_gaps_are_split_in_the_sii() {
    let pdos = "<TxPdo Fixed=\"1\" Sm=\"3\"><Index>#x1A00</Index><Name>In</Name>\n\
<Entry><Index>#x6000</Index><SubIndex>0</SubIndex><BitLen>320</BitLen><Name>s</Name><DataType>STRING(40)</DataType></Entry>\n\
<Entry><Index>#x0</Index><BitLen>320</BitLen></Entry>\n\
</TxPdo>";
    let (d, _) = one(&device("", pdos));
    let image = od::sii::parse(&od::sii::write(&d, 1).unwrap()).unwrap();
    let tx = image.category(od::sii::category::TXPDO).unwrap();
    let entries: Vec<(u16, u8)> = tx[8..]
        .chunks(8)
        .map(|e| (u16::from_le_bytes([e[0], e[1]]), e[5]))
        .collect();
    assert_eq!(entries, [(0x6000, 255), (0, 255), (0, 65)]);
}

/// A finding about the device as a whole (a missing mandatory object) is placed at its `Device` element
/// (line 4, after `<Descriptions><Groups/><Devices>`).
#[test]
fn device_findings_are_at_the_device_element() {
    let objects = "<Object><Index>#x1008</Index><Name>Device name</Name><Type>STRING(4)</Type><BitSize>32</BitSize></Object>";
    let text = device(objects, "<Mailbox><CoE/></Mailbox>");
    let reading = read(&text);
    let found: Vec<String> =
        od::validate::validate_mapped(&reading.devices[0], &reading.sources[0])
            .iter()
            .map(|f| {
                let p = f.position.expect("a position");
                format!("{}:{}: {f}", p.line, p.column)
            })
            .collect();
    assert_eq!(
        found,
        [
            "4:33: warning: object 0x1000 (device type) is mandatory and missing",
            "4:33: warning: object 0x1018 (identity) is mandatory and missing",
        ]
    );
}

/// Localized names of slots and module classes: the English one (LcId 1033) wherever it comes, else the
/// first.
#[test]
fn slot_and_module_class_names_prefer_english() {
    let text = MODULAR
        .replace(
            "<Name LcId=\"1031\">Achse 1</Name><Name LcId=\"1033\">Axis 1</Name>",
            "<Name LcId=\"1033\">Axis 1</Name><Name LcId=\"1031\">Achse 1</Name>",
        )
        .replace(
            "<Name>Terminals</Name>",
            "<Name LcId=\"1031\">Klemmen</Name><Name LcId=\"1036\">Bornes</Name>",
        )
        .replace(
            "<Name LcId=\"1033\">Digital inputs</Name>",
            "<Name LcId=\"1031\">Digitale Eingänge</Name><Name LcId=\"1033\">Digital inputs</Name><Name LcId=\"1036\">Entrées</Name>",
        );
    let reading = read(&text);
    let slots = reading.devices[0]
        .ethercat
        .as_ref()
        .unwrap()
        .slots
        .as_ref()
        .unwrap();
    assert_eq!(slots.slots[0].name, "Axis 1");
    assert_eq!(slots.slots[1].name, "Klemmen");
    assert_eq!(slots.slots[1].module_classes[0].name, "Digital inputs");
}

/// The PDO after one that refers to a template gets its own entries.
#[test]
fn a_pdo_after_a_template_pdo_is_read() {
    let pdos = "<RxPdo Ref=\"DigOutputBit\" Sm=\"2\"><Index>#x1601</Index><Name>Ref</Name>\n\
<Entry><Index>#x0</Index><BitLen>16</BitLen></Entry></RxPdo>\n\
<RxPdo Sm=\"2\"><Index>#x1600</Index><Name>Out</Name>\n\
<Entry><Index>#x0</Index><BitLen>8</BitLen></Entry></RxPdo>";
    let (d, _) = one(&device("", pdos));
    let rx = &d.ethercat.as_ref().unwrap().rx_pdos;
    assert_eq!(rx.len(), 1);
    assert_eq!(
        (rx[0].index, rx[0].name.as_str(), rx[0].entries.len()),
        (0x1600, "Out", 1)
    );
    assert_eq!(rx[0].entries[0].bit_len, 8);
}
