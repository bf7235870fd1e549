//! Constructs of real vendor ESI files that the established tools load, each reproduced in a small file of
//! its own: what the reader makes of it (exact model values) and the warning it gives (exact text, line
//! and column). Each file is also written and read back.

use od::esi;
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
               <Sm StartAddress=\"#x1800\" ControlByte=\"#x20\" Enable=\"#x0\">Inputs</Sm>";
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
        ]
    );
    // The SII SyncM category: 8 bytes per sync manager, the enable byte at 6 (Virtual is bit 2, OpOnly
    // bit 3).
    let image = od::sii::parse(&od::sii::write(&d, 1).unwrap()).unwrap();
    let syncm = image.category(od::sii::category::SYNCM).unwrap();
    assert_eq!([syncm[6], syncm[14], syncm[22]], [9, 0x0D, 0]);

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
