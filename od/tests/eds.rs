//! CiA 306 EDS and DCF: a hand-written EDS read into exact objects, byte-exact writer output, a DCF with
//! commissioning and parameter values through write and read, errors with their line and column, and
//! random descriptions through write → read (`eds_random`).

mod support;

use od::device::{CanInfo, Commissioning, FileInfo, Identity};
use od::{
    eds, AccessType, DataType, DefaultValue, DeviceDescription, Object, ObjectKind, PdoMapping,
    SubObject, Value,
};

/// A small EDS written by hand: BOM, CR LF and LF lines, keys and sections in any case, comments,
/// unknown keys and sections, a compact array with names, `$NODEID`, an unlisted object.
const SMALL_EDS: &str = concat!(
    "\u{FEFF}; A hand-written EDS\r\n",
    "[FileInfo]\r\n",
    "FileName=small.eds\r\n",
    "FileVersion=1\r\n",
    "FileRevision=2\r\n",
    "EDSVersion=4.0\r\n",
    "Description=Small test device\r\n",
    "CreationTime=09:15AM\r\n",
    "CreationDate=01-02-2024\r\n",
    "CreatedBy=Tester\r\n",
    "\r\n",
    "[deviceinfo]\n",
    "VendorName=ACME µ\n",
    "vendornumber=0x0000012A\n",
    "ProductName=Widget\n",
    "ProductNumber=42\n",
    "RevisionNumber=0x00010002\n",
    "OrderCode=W-1\n",
    "BaudRate_125=1\n",
    "BaudRate_500=1\n",
    "  BaudRate_1000 = 1\n",
    "BaudRate_800=0\n",
    "SimpleBootUpSlave=1\n",
    "Granularity=8\n",
    "NrOfRXPDO=1\n",
    "NrOfTXPDO=2\n",
    "LSS_Supported=1\n",
    "CompactPDO=0\n",
    "SomeVendorKey=whatever\n",
    "\n",
    "[DummyUsage]\n",
    "Dummy0002=1\n",
    "Dummy0005=1\n",
    "Dummy0007=0\n",
    "\n",
    "[Comments]\n",
    "Lines=2\n",
    "Line1=first line\n",
    "Line2=  second ; not a comment  \n",
    "\n",
    "[MandatoryObjects]\n",
    "SupportedObjects=2\n",
    "1=0x1000\n",
    "2=0x1018\n",
    "\n",
    "[1000]\n",
    "ParameterName=Device type\n",
    "ObjectType=0x7\n",
    ";StorageLocation=ROM\n",
    "DataType=0x0007\n",
    "AccessType=ro\n",
    "DefaultValue=0x00020192\n",
    "PDOMapping=0\n",
    "\n",
    "[1018]\n",
    "ParameterName=Identity\n",
    "ObjectType=0x9\n",
    "SubNumber=2\n",
    "\n",
    "[1018sub0]\n",
    "ParameterName=Highest sub-index supported\n",
    "DataType=0x0005\n",
    "AccessType=const\n",
    "DefaultValue=1\n",
    "\n",
    "[1018SUB1]\n",
    "parametername=Vendor-ID\n",
    "DATATYPE=7\n",
    "accesstype=RO\n",
    "DefaultValue=0x12A\n",
    "\n",
    "[OptionalObjects]\n",
    "SupportedObjects=2\n",
    "1=0x1800\n",
    "2=0x6000\n",
    "\n",
    "[1800]\n",
    "ParameterName=TPDO 1 communication parameter\n",
    "ObjectType=0x9\n",
    "SubNumber=3\n",
    "\n",
    "[1800sub0]\n",
    "ParameterName=Highest sub-index supported\n",
    "ObjectType=0x7\n",
    "DataType=0x0005\n",
    "AccessType=ro\n",
    "DefaultValue=2\n",
    "\n",
    "[1800sub1]\n",
    "ParameterName=COB-ID used by TPDO 1\n",
    "DataType=0x0007\n",
    "AccessType=rw\n",
    "DefaultValue=$nodeid + 0x180\n",
    "\n",
    "[1800sub2]\n",
    "ParameterName=Transmission type\n",
    "DataType=0x0005\n",
    "AccessType=rw\n",
    "DefaultValue=0xFF\n",
    "LowLimit=0\n",
    "HighLimit=0xFF\n",
    "\n",
    "[6000]\n",
    "ParameterName=Inputs\n",
    "ObjectType=0x8\n",
    "DataType=0x0003\n",
    "AccessType=ro\n",
    "DefaultValue=-5\n",
    "PDOMapping=1\n",
    "LowLimit=0xFF00\n",
    "HighLimit=1000\n",
    "CompactSubObj=3\n",
    "\n",
    "[6000Name]\n",
    "NrOfEntries=2\n",
    "1=Input A\n",
    "3=Input C\n",
    "\n",
    "[ManufacturerObjects]\n",
    "SupportedObjects=3\n",
    "1=0x2000\n",
    "2=0x2001\n",
    "3=0x2002\n",
    "\n",
    "[2000]\n",
    "ParameterName=Label\n",
    "DataType=0x0009\n",
    "AccessType=rw\n",
    "DefaultValue=hello world\n",
    "PDOMapping=0\n",
    "StorageLocation=RAM\n",
    "\n",
    "[2001]\n",
    "ParameterName=Blob\n",
    "ObjectType=0x2\n",
    "DataType=0x000F\n",
    "AccessType=rw\n",
    "UploadFile=blob.bin\n",
    "\n",
    "[2002]\n",
    "ParameterName=Key\n",
    "DataType=0x000A\n",
    "AccessType=rww\n",
    "DefaultValue=01 02 0a\n",
    "PDOMapping=1\n",
    "\n",
    "# Not in any object list, read all the same.\n",
    "[2003]\n",
    "ParameterName=Gain\n",
    "DataType=0x0008\n",
    "AccessType=rw\n",
    "DefaultValue=1.5\n",
    "PDOMapping=1\n",
    "\n",
    "[Tools]\n",
    "Editor=by hand\n",
);

/// [`SMALL_EDS`] read.
fn small_eds() -> DeviceDescription {
    eds::read(SMALL_EDS.as_bytes(), "small.eds").unwrap()
}

#[test]
fn small_hand_written_eds_reads_into_exact_file_info_identity_and_can_parts() {
    let desc = small_eds();
    assert_eq!(
        desc.file_info,
        FileInfo {
            file_name: "small.eds".into(),
            file_version: "1".into(),
            file_revision: "2".into(),
            format_version: "4.0".into(),
            description: "Small test device".into(),
            creation_time: "09:15AM".into(),
            creation_date: "01-02-2024".into(),
            created_by: "Tester".into(),
            ..FileInfo::default()
        }
    );
    assert_eq!(
        desc.identity,
        Identity {
            vendor_id: 0x12A,
            vendor_name: "ACME µ".into(),
            product_code: 42,
            revision: 0x0001_0002,
            product_name: "Widget".into(),
            order_code: "W-1".into(),
            ..Default::default()
        }
    );
    assert_eq!(
        desc.can,
        Some(CanInfo {
            baud_rates: vec![125, 500, 1000],
            simple_boot_up_master: false,
            simple_boot_up_slave: true,
            granularity: 8,
            dynamic_channels: 0,
            group_messaging: false,
            nr_of_rx_pdo: 1,
            nr_of_tx_pdo: 2,
            lss_supported: true,
            dummy_usage: vec![2, 5],
        })
    );
    assert_eq!(desc.comments, ["first line", "second ; not a comment"]);
    assert_eq!(desc.commissioning, None);
}

#[test]
fn small_hand_written_eds_reads_into_exact_communication_objects() {
    let desc = small_eds();
    let d = &desc.dictionary;
    assert_eq!(
        d.objects().map(|o| o.index).collect::<Vec<_>>(),
        [0x1000, 0x1018, 0x1800, 0x2000, 0x2001, 0x2002, 0x2003, 0x6000]
    );
    assert_eq!(
        d.object(0x1000).unwrap(),
        &Object::var(
            0x1000,
            SubObject::new("Device type", DataType::Unsigned32, AccessType::Ro)
                .with_default(Value::Uint(0x0002_0192))
        )
    );
    assert_eq!(
        d.object(0x1018).unwrap(),
        &Object::structured(0x1018, "Identity", ObjectKind::Record)
            .with_sub(
                0,
                SubObject::new(
                    "Highest sub-index supported",
                    DataType::Unsigned8,
                    AccessType::Const
                )
                .with_default(Value::Uint(1))
            )
            .with_sub(
                1,
                SubObject::new("Vendor-ID", DataType::Unsigned32, AccessType::Ro)
                    .with_default(Value::Uint(0x12A))
            )
    );
    let mut cob_id = SubObject::new(
        "COB-ID used by TPDO 1",
        DataType::Unsigned32,
        AccessType::Rw,
    )
    .with_default(Value::Uint(0x180));
    cob_id.default = Some(DefaultValue {
        value: Value::Uint(0x180),
        plus_node_id: true,
    });
    assert_eq!(
        d.object(0x1800).unwrap(),
        &Object::structured(0x1800, "TPDO 1 communication parameter", ObjectKind::Record)
            .with_sub(
                0,
                SubObject::new(
                    "Highest sub-index supported",
                    DataType::Unsigned8,
                    AccessType::Ro
                )
                .with_default(Value::Uint(2))
            )
            .with_sub(1, cob_id)
            .with_sub(
                2,
                SubObject::new("Transmission type", DataType::Unsigned8, AccessType::Rw)
                    .with_default(Value::Uint(0xFF))
                    .with_limits(Some(Value::Uint(0)), Some(Value::Uint(0xFF)))
            )
    );
    // The EDS has no node-ID: the current value of a `$NODEID` default is the offset alone.
    assert_eq!(d.read_value(0x1800, 1).unwrap(), Value::Uint(0x180));
}

#[test]
fn small_hand_written_eds_reads_into_exact_application_objects() {
    let desc = small_eds();
    let d = &desc.dictionary;
    let input = |name: &str| {
        SubObject::new(name, DataType::Integer16, AccessType::Ro)
            .with_default(Value::Int(-5))
            .with_limits(Some(Value::Int(-256)), Some(Value::Int(1000)))
            .with_pdo(PdoMapping::Tpdo)
    };
    assert_eq!(
        d.object(0x6000).unwrap(),
        &Object::structured(0x6000, "Inputs", ObjectKind::Array)
            .with_sub(
                0,
                SubObject::new("NrOfObjects", DataType::Unsigned8, AccessType::Ro)
                    .with_default(Value::Uint(3))
            )
            .with_sub(1, input("Input A"))
            .with_sub(2, input("Inputs2"))
            .with_sub(3, input("Input C"))
    );
    assert_eq!(
        d.object(0x2000).unwrap(),
        &Object::var(
            0x2000,
            SubObject::new("Label", DataType::VisibleString, AccessType::Rw)
                .with_default(Value::String("hello world".into()))
        )
    );
    let blob = d.object(0x2001).unwrap();
    assert_eq!(
        blob,
        &Object::var(
            0x2001,
            SubObject::new("Blob", DataType::Domain, AccessType::Rw)
        )
    );
    assert_eq!(blob.kind, ObjectKind::Domain);
    assert_eq!(
        d.object(0x2002).unwrap(),
        &Object::var(
            0x2002,
            SubObject::new("Key", DataType::OctetString, AccessType::Rww)
                .with_default(Value::Bytes(vec![1, 2, 0x0A]))
                .with_pdo(PdoMapping::Rpdo)
        )
    );
    assert_eq!(
        d.object(0x2003).unwrap(),
        &Object::var(
            0x2003,
            SubObject::new("Gain", DataType::Real32, AccessType::Rw)
                .with_default(Value::Real32(1.5))
                .with_pdo(PdoMapping::Both)
        )
    );
}

#[test]
fn small_hand_written_eds_written_reads_back_the_same() {
    let desc = small_eds();
    // What the writer makes of it reads back the same.
    let again = eds::read(eds::write_eds(&desc).as_bytes(), "again.eds").unwrap();
    assert_eq!(again, desc);
}

fn golden_description() -> DeviceDescription {
    let mut desc = DeviceDescription {
        identity: Identity {
            vendor_id: 0x12A,
            vendor_name: "ACME".into(),
            product_code: 0x42,
            revision: 1,
            product_name: "Widget".into(),
            order_code: "W-1".into(),
            ..Default::default()
        },
        file_info: FileInfo {
            file_name: "golden.eds".into(),
            file_version: "1".into(),
            file_revision: "0".into(),
            format_version: "4.0".into(),
            description: "Golden".into(),
            ..FileInfo::default()
        },
        can: Some(CanInfo {
            baud_rates: vec![250, 500],
            nr_of_rx_pdo: 1,
            nr_of_tx_pdo: 1,
            dummy_usage: vec![5],
            ..CanInfo::default()
        }),
        comments: vec!["hello".into()],
        ..DeviceDescription::default()
    };
    let d = &mut desc.dictionary;
    d.insert(Object::var(
        0x1000,
        SubObject::new("Device type", DataType::Unsigned32, AccessType::Ro)
            .with_default(Value::Uint(0x0002_0192)),
    ));
    d.insert(
        Object::structured(0x1018, "Identity", ObjectKind::Record)
            .with_sub(
                0,
                SubObject::new(
                    "Highest sub-index supported",
                    DataType::Unsigned8,
                    AccessType::Const,
                )
                .with_default(Value::Uint(1)),
            )
            .with_sub(
                1,
                SubObject::new("Vendor-ID", DataType::Unsigned32, AccessType::Ro)
                    .with_default(Value::Uint(0x12A)),
            ),
    );
    let mut cob_id = SubObject::new("COB-ID", DataType::Unsigned32, AccessType::Rw)
        .with_default(Value::Uint(0x180));
    cob_id.default = Some(DefaultValue {
        value: Value::Uint(0x180),
        plus_node_id: true,
    });
    d.insert(
        Object::structured(0x1800, "TPDO 1", ObjectKind::Record)
            .with_sub(
                0,
                SubObject::new("Count", DataType::Unsigned8, AccessType::Ro)
                    .with_default(Value::Uint(1)),
            )
            .with_sub(1, cob_id),
    );
    d.insert(Object::var(
        0x2000,
        SubObject::new("Label", DataType::VisibleString, AccessType::Rw)
            .with_default(Value::String("hi".into())),
    ));
    d.insert(Object::var(
        0x6000,
        SubObject::new("Input", DataType::Integer16, AccessType::Ro)
            .with_default(Value::Int(-5))
            .with_limits(Some(Value::Int(-100)), Some(Value::Int(100)))
            .with_pdo(PdoMapping::Tpdo),
    ));
    desc
}

const GOLDEN_EDS: &str = "[FileInfo]\r
FileName=golden.eds\r
FileVersion=1\r
FileRevision=0\r
EDSVersion=4.0\r
Description=Golden\r
CreationTime=\r
CreationDate=\r
CreatedBy=\r
ModificationTime=\r
ModificationDate=\r
ModifiedBy=\r
\r
[DeviceInfo]\r
VendorName=ACME\r
VendorNumber=0x0000012A\r
ProductName=Widget\r
ProductNumber=0x00000042\r
RevisionNumber=0x00000001\r
OrderCode=W-1\r
BaudRate_10=0\r
BaudRate_20=0\r
BaudRate_50=0\r
BaudRate_125=0\r
BaudRate_250=1\r
BaudRate_500=1\r
BaudRate_800=0\r
BaudRate_1000=0\r
SimpleBootUpMaster=0\r
SimpleBootUpSlave=1\r
Granularity=8\r
DynamicChannelsSupported=0\r
GroupMessaging=0\r
NrOfRXPDO=1\r
NrOfTXPDO=1\r
LSS_Supported=0\r
\r
[DummyUsage]\r
Dummy0001=0\r
Dummy0002=0\r
Dummy0003=0\r
Dummy0004=0\r
Dummy0005=1\r
Dummy0006=0\r
Dummy0007=0\r
\r
[Comments]\r
Lines=1\r
Line1=hello\r
\r
[MandatoryObjects]\r
SupportedObjects=2\r
1=0x1000\r
2=0x1018\r
\r
[OptionalObjects]\r
SupportedObjects=2\r
1=0x1800\r
2=0x6000\r
\r
[ManufacturerObjects]\r
SupportedObjects=1\r
1=0x2000\r
\r
[1000]\r
ParameterName=Device type\r
ObjectType=0x7\r
DataType=0x0007\r
AccessType=ro\r
DefaultValue=0x00020192\r
PDOMapping=0\r
\r
[1018]\r
ParameterName=Identity\r
ObjectType=0x9\r
SubNumber=0x2\r
\r
[1018sub0]\r
ParameterName=Highest sub-index supported\r
ObjectType=0x7\r
DataType=0x0005\r
AccessType=const\r
DefaultValue=0x01\r
PDOMapping=0\r
\r
[1018sub1]\r
ParameterName=Vendor-ID\r
ObjectType=0x7\r
DataType=0x0007\r
AccessType=ro\r
DefaultValue=0x0000012A\r
PDOMapping=0\r
\r
[1800]\r
ParameterName=TPDO 1\r
ObjectType=0x9\r
SubNumber=0x2\r
\r
[1800sub0]\r
ParameterName=Count\r
ObjectType=0x7\r
DataType=0x0005\r
AccessType=ro\r
DefaultValue=0x01\r
PDOMapping=0\r
\r
[1800sub1]\r
ParameterName=COB-ID\r
ObjectType=0x7\r
DataType=0x0007\r
AccessType=rw\r
DefaultValue=$NODEID+0x180\r
PDOMapping=0\r
\r
[2000]\r
ParameterName=Label\r
ObjectType=0x7\r
DataType=0x0009\r
AccessType=rw\r
DefaultValue=hi\r
PDOMapping=0\r
\r
[6000]\r
ParameterName=Input\r
ObjectType=0x7\r
DataType=0x0003\r
AccessType=ro\r
DefaultValue=-5\r
PDOMapping=1\r
LowLimit=-100\r
HighLimit=100\r
";

#[test]
fn writes_byte_exact_eds() {
    let desc = golden_description();
    let text = eds::write_eds(&desc);
    assert_eq!(text, GOLDEN_EDS);
    assert_eq!(eds::write_eds(&desc), text, "stable");
    assert_eq!(eds::read(text.as_bytes(), "golden.eds").unwrap(), desc);
}

#[test]
fn writes_byte_exact_dcf() {
    let mut desc = golden_description();
    desc.commissioning = Some(Commissioning {
        node_id: Some(5),
        node_name: "Left".into(),
        baud_rate: 500,
        net_number: 1,
        network_name: "Line 3".into(),
        canopen_manager: false,
        lss_serial_number: 0x1234,
    });
    desc.dictionary.reset(5);
    desc.dictionary
        .store_value(0x2000, 0, &Value::String("yo".into()))
        .unwrap();
    desc.dictionary
        .store_value(0x6000, 0, &Value::Int(7))
        .unwrap();
    let text = eds::write_dcf(&desc);
    let expected = GOLDEN_EDS
        .replace(
            "LSS_Supported=0\r\n\r\n",
            "LSS_Supported=0\r\n\r\n[DeviceComissioning]\r\nNodeID=5\r\nNodeName=Left\r\nBaudrate=500\r\n\
             NetNumber=1\r\nNetworkName=Line 3\r\nCANopenManager=0\r\nLSS_SerialNumber=0x00001234\r\n\r\n",
        )
        .replace(
            "DefaultValue=hi\r\nPDOMapping=0\r\n",
            "DefaultValue=hi\r\nPDOMapping=0\r\nParameterValue=yo\r\n",
        )
        .replace(
            "HighLimit=100\r\n",
            "HighLimit=100\r\nParameterValue=7\r\n",
        );
    assert_eq!(text, expected);
    let expected_text = expected;

    // Read back: the values that differ from their defaults come back as set explicitly, the others as
    // the defaults for node 5.
    let back = eds::read(text.as_bytes(), "golden.dcf").unwrap();
    assert_eq!(back.commissioning, desc.commissioning);
    assert_eq!(
        back.dictionary.read_value(0x1800, 1).unwrap(),
        Value::Uint(0x185)
    );
    let label = back.dictionary.entry(0x2000, 0).unwrap();
    assert_eq!(label.value, b"yo");
    assert!(label.value_set);
    let mut expected = desc.clone();
    for (index, sub) in [(0x2000, 0), (0x6000, 0)] {
        entry_mut(&mut expected, index, sub).value_set = true;
    }
    assert_eq!(back, expected);

    // Configured (what `esi-gen dcf` does): every writable entry gets its value, the COB-ID still at its
    // `$NODEID` default relative to the node-ID; the read-only ones do not.
    let mut configured = desc.clone();
    configured.configure_writable();
    let text = eds::write_dcf(&configured);
    let expected = expected_text.replace(
        "DefaultValue=$NODEID+0x180\r\nPDOMapping=0\r\n",
        "DefaultValue=$NODEID+0x180\r\nPDOMapping=0\r\nParameterValue=$NODEID+0x180\r\n",
    );
    assert_eq!(text, expected);
    let back = eds::read(text.as_bytes(), "configured.dcf").unwrap();
    // 0x6000 (read-only, 7 instead of its default -5) comes back set, as above.
    entry_mut(&mut configured, 0x6000, 0).value_set = true;
    assert_eq!(back, configured);
    let cob = back.dictionary.entry(0x1800, 1).unwrap();
    assert!(cob.value_set && cob.value_plus_node_id);
    assert_eq!(cob.value, [0x85, 0x01, 0, 0]);
    assert!(!back.dictionary.entry(0x1018, 1).unwrap().value_set);
}

fn entry_mut(desc: &mut DeviceDescription, index: u16, sub: u8) -> &mut SubObject {
    desc.dictionary
        .object_mut(index)
        .and_then(|o| o.subs.get_mut(&sub))
        .unwrap()
}

/// A description without a node-ID (an EDS, Lely's DCFs of an unconfigured node) is written as a DCF
/// without `NodeID=`: a made-up node-ID would change what every `$NODEID` value means (Lely's
/// cocatd.dcf once came back with 0x1014 = 0x81 for its `$NODEID+0x80`). Read back, the node is still
/// unconfigured and the `$NODEID` values are resolved with 0, as in the EDS. A description without
/// commissioning values (an EDS, ros_canopen's DCFs) is written without `[DeviceComissioning]`.
#[test]
fn dcf_without_a_node_id_has_none() {
    let desc = golden_description();
    assert_eq!(desc.commissioning, None);
    assert_eq!(eds::write_dcf(&desc), GOLDEN_EDS);
    // The description holds the EDS values (`$NODEID` resolved with 0): still defaults, so no
    // ParameterValue at all.
    let text = {
        let mut desc = desc.clone();
        desc.commissioning = Some(Commissioning::default());
        eds::write_dcf(&desc)
    };
    let expected = GOLDEN_EDS.replace(
        "LSS_Supported=0\r\n\r\n",
        "LSS_Supported=0\r\n\r\n[DeviceComissioning]\r\nNodeName=\r\nBaudrate=0\r\nNetNumber=0\r\n\
         NetworkName=\r\nCANopenManager=0\r\n\r\n",
    );
    assert_eq!(text, expected);
    let back = eds::read(text.as_bytes(), "unconfigured.dcf").unwrap();
    assert_eq!(back.commissioning, Some(Commissioning::default()));
    assert_eq!(
        back.dictionary.read_value(0x1800, 1).unwrap(),
        Value::Uint(0x180)
    );
    assert_eq!(back.dictionary, desc.dictionary);
}

const SMALL_DCF: &str = "[FileInfo]
FileName=node.dcf
EDSVersion=4.0

[DeviceInfo]
VendorName=ACME

[DeviceComissioning]
NodeID=0x10
NodeName=Left axis
Baudrate=500
NetNumber=1
NetworkName=Line 3
CANopenManager=1
LSS_SerialNumber=0x1234

[OptionalObjects]
SupportedObjects=3
1=0x1017
2=0x1400
3=0x1800

[1017]
ParameterName=Producer heartbeat time
DataType=0x0006
AccessType=rw
DefaultValue=0
ParameterValue=1000

[1400]
ParameterName=RPDO 1 communication parameter
ObjectType=0x9
[1400sub1]
ParameterName=COB-ID used by RPDO 1
DataType=0x0007
AccessType=rw
DefaultValue=0x200+$NODEID
ParameterValue=$NODEID+0x300

[1800]
ParameterName=TPDO 1 communication parameter
ObjectType=0x9
[1800sub1]
ParameterName=COB-ID used by TPDO 1
DataType=0x0007
AccessType=rw
DefaultValue=$NODEID+0x180
[1800sub2]
ParameterName=Transmission type
DataType=0x0005
AccessType=rw
DefaultValue=255
ParameterValue=0x01

[ManufacturerObjects]
SupportedObjects=2
1=0x2000
2=0x2001

[2000]
ParameterName=Gains
ObjectType=0x8
DataType=0x0005
AccessType=rw
DefaultValue=7
CompactSubObj=2
[2000Value]
NrOfEntries=1
2=9

[2001]
ParameterName=Name
DataType=0x0009
AccessType=rw
ParameterValue=hello
";

#[test]
fn reads_a_dcf_and_writes_it_back() {
    let desc = eds::read(SMALL_DCF.as_bytes(), "node.dcf").unwrap();
    assert_eq!(
        desc.commissioning,
        Some(Commissioning {
            node_id: Some(0x10),
            node_name: "Left axis".into(),
            baud_rate: 500,
            net_number: 1,
            network_name: "Line 3".into(),
            canopen_manager: true,
            lss_serial_number: 0x1234,
        })
    );
    let d = &desc.dictionary;
    let heartbeat = d.entry(0x1017, 0).unwrap();
    assert_eq!(d.read_value(0x1017, 0).unwrap(), Value::Uint(1000));
    assert!(heartbeat.value_set);
    assert_eq!(heartbeat.default, Some(DefaultValue::plain(Value::Uint(0))));

    // `$NODEID` defaults keep the offset, and the value is resolved with NodeID.
    let tpdo = d.entry(0x1800, 1).unwrap();
    assert_eq!(
        tpdo.default,
        Some(DefaultValue {
            value: Value::Uint(0x180),
            plus_node_id: true
        })
    );
    assert_eq!(d.read_value(0x1800, 1).unwrap(), Value::Uint(0x190));
    assert!(!tpdo.value_set);
    let rpdo = d.entry(0x1400, 1).unwrap();
    assert_eq!(
        rpdo.default,
        Some(DefaultValue {
            value: Value::Uint(0x200),
            plus_node_id: true
        })
    );
    assert_eq!(d.read_value(0x1400, 1).unwrap(), Value::Uint(0x310));
    assert!(rpdo.value_set);
    assert_eq!(d.read_value(0x1800, 2).unwrap(), Value::Uint(1));

    // Compact array: [2000Value] sets sub-index 2 only.
    assert_eq!(d.read_value(0x2000, 1).unwrap(), Value::Uint(7));
    assert!(!d.entry(0x2000, 1).unwrap().value_set);
    assert_eq!(d.read_value(0x2000, 2).unwrap(), Value::Uint(9));
    assert!(d.entry(0x2000, 2).unwrap().value_set);
    assert_eq!(d.entry(0x2000, 2).unwrap().name, "Gains2");

    let name = d.entry(0x2001, 0).unwrap();
    assert_eq!(name.default, None);
    assert_eq!(name.value, b"hello");

    let text = eds::write_dcf(&desc);
    assert!(text.contains("NodeID=16\r\n"));
    assert!(text.contains("DefaultValue=$NODEID+0x180\r\nPDOMapping=0\r\n\r\n"));
    // `ParameterValue=$NODEID+0x300` stays relative to the node-ID.
    assert!(text.contains(
        "DefaultValue=$NODEID+0x200\r\nPDOMapping=0\r\nParameterValue=$NODEID+0x300\r\n"
    ));
    // The compact array's `[2000Value]` entry is the ParameterValue of its sub-index section.
    assert!(text.contains(
        "[2000sub2]\r\nParameterName=Gains2\r\nObjectType=0x7\r\nDataType=0x0005\r\nAccessType=rw\r\n\
         DefaultValue=0x07\r\nPDOMapping=0\r\nParameterValue=0x09\r\n"
    ));
    assert_eq!(eds::read(text.as_bytes(), "again.dcf").unwrap(), desc);

    // As an EDS: the commissioning values and the values the DCF set stay (an EDS may carry both), and
    // read back the same.
    let text = eds::write_eds(&desc);
    assert!(text.contains("[DeviceComissioning]\r\nNodeID=16\r\n"));
    assert_eq!(eds::read(text.as_bytes(), "node.eds").unwrap(), desc);

    // Reset and without commissioning values, a plain EDS: no ParameterValue, `$NODEID` defaults
    // resolved with node 0.
    let mut plain = desc.clone();
    plain.commissioning = None;
    plain.dictionary.reset(0);
    let text = eds::write_eds(&plain);
    assert!(!text.contains("ParameterValue") && !text.contains("DeviceComissioning"));
    let as_eds = eds::read(text.as_bytes(), "node.eds").unwrap();
    assert_eq!(as_eds, plain);
    assert_eq!(
        as_eds.dictionary.read_value(0x1800, 1).unwrap(),
        Value::Uint(0x180)
    );
    assert_eq!(
        as_eds.dictionary.read_value(0x1017, 0).unwrap(),
        Value::Uint(0)
    );
}

#[test]
fn node_id_forms_and_odd_spellings() {
    let text = "[2000]\nParameterName=A\nDataType=7\nAccessType=rw\nDefaultValue=$NODEID\n\
                [2001]\nParameterName=B\nDataType=0x0006\nAccessType=rw\nDefaultValue= 0x40 + $NodeID \n\
                [2002]\nParameterName=C\nDataType=0x0009\nAccessType=ro\nDefaultValue=$NODEID+1\n\
                [2003]\nParameterName=D\nDataType=0x0003\nAccessType=ro\nDefaultValue=\nPDOMapping=0x1\n\
                [2004]\nParameterName=E\nDataType=0x0001\nAccessType=ro\nDefaultValue=1\n\
                [2005]\nParameterName=F\nDataType=0x0004\nAccessType=ro\nDefaultValue=0xFFFFFFFF\n";
    let desc = eds::read(text.as_bytes(), "forms.eds").unwrap();
    let d = &desc.dictionary;
    let default = |i| d.entry(i, 0).unwrap().default.clone();
    assert_eq!(
        default(0x2000),
        Some(DefaultValue {
            value: Value::Uint(0),
            plus_node_id: true
        })
    );
    assert_eq!(
        default(0x2001),
        Some(DefaultValue {
            value: Value::Uint(0x40),
            plus_node_id: true
        })
    );
    // In a string `$NODEID` is just text.
    assert_eq!(
        default(0x2002),
        Some(DefaultValue::plain(Value::String("$NODEID+1".into())))
    );
    // An empty numeric default is no default.
    assert_eq!(default(0x2003), None);
    assert_eq!(d.entry(0x2003, 0).unwrap().pdo, PdoMapping::Tpdo);
    assert_eq!(
        default(0x2004),
        Some(DefaultValue::plain(Value::Bool(true)))
    );
    assert_eq!(default(0x2005), Some(DefaultValue::plain(Value::Int(-1))));
}

#[test]
fn latin1_files_read_as_iso_8859_1() {
    let text = b"[DeviceInfo]\r\nVendorName=M\xFCller \xB5Tec\r\nProductName=Caf\xE9\r\n";
    let desc = eds::read(text, "latin1.eds").unwrap();
    assert_eq!(desc.identity.vendor_name, "Müller µTec");
    assert_eq!(desc.identity.product_name, "Café");
}

/// `text` must fail to read with an error at `line:column` whose message contains `message`.
fn assert_error(text: &[u8], line: u32, column: u32, message: &str) {
    let err = eds::read(text, "bad.eds").expect_err("the file should be refused");
    assert_eq!(
        (err.position.line, err.position.column),
        (line, column),
        "{err}"
    );
    assert_eq!(err.source_name, "bad.eds");
    assert!(
        err.message.contains(message),
        "`{}` does not contain `{message}`",
        err.message
    );
}

/// `text` must read with exactly the warnings `expected`, each `line:column: message`.
fn assert_warnings(text: &[u8], expected: &[&str]) -> od::DeviceDescription {
    let mut reading = eds::read_file(text, "odd.eds").unwrap_or_else(|e| panic!("{e}"));
    let got: Vec<String> = reading
        .findings
        .iter()
        .map(|f| {
            let p = f.position.expect("a reader warning has a position");
            assert_eq!(f.severity, od::Severity::Warning);
            format!("{}:{}: {}", p.line, p.column, f.message)
        })
        .collect();
    assert_eq!(got, expected);
    reading.devices.pop().expect("one device")
}

#[test]
fn unknown_data_types_are_domains_with_a_warning() {
    let desc = assert_warnings(
        b"[1000]\nParameterName=Device type\nDataType=0x0017\nAccessType=ro\n\
          [1600]\nParameterName=Mapping\nDataType=0x0021\nAccessType=ro\n",
        &[
            "3:10: DataType= in [1000]: 0x0017 is not a CiA 301 data type; the entry is read as DOMAIN",
            "7:10: DataType= in [1600]: 0x0021 is a complex or profile data type; the entry is read as DOMAIN",
        ],
    );
    assert_eq!(
        desc.dictionary.entry(0x1000, 0).unwrap().data_type,
        DataType::Domain
    );
    assert_eq!(
        desc.dictionary.entry(0x1600, 0).unwrap().data_type,
        DataType::Domain
    );
}

const VAR_HEAD: &str = "[FileInfo]\nFileName=bad.eds\n[1000]\nParameterName=Device type\n";

#[test]
fn errors_name_line_and_column() {
    let with = |rest: &str| format!("{VAR_HEAD}{rest}").into_bytes();
    assert_error(
        &with("DataType=zz\nAccessType=ro\n"),
        5,
        10,
        "DataType= in [1000]: expected a CiA 301 data type index like 0x0007, found `zz`",
    );
    assert_error(
        &with("DataType=0x0007\n  AccessType = rx\n"),
        6,
        16,
        "AccessType= in [1000]: expected ro, wo, rw, rwr, rww or const, found `rx`",
    );
    assert_error(
        &with("DataType=0x0005\nAccessType=ro\nPDOMapping=2\n"),
        7,
        12,
        "expected 0 or 1",
    );
    assert_error(&with("AccessType=ro\n"), 3, 2, "[1000] has no DataType=");
    assert_error(
        &with("DataType=0x0007\nAccessType=ro\nObjectType=0x3\n"),
        7,
        12,
        "an object code",
    );
    assert_error(
        &with("DataType=0x0007\nAccessType=ro\ndatatype=0x0007\n"),
        7,
        1,
        "appears a second time in [1000] (first at line 5)",
    );
    assert_error(
        &with("DataType=0x0007\nAccessType=ro\n[1000]\nParameterName=again\n"),
        7,
        2,
        "section [1000] appears a second time (first at line 3)",
    );
    assert_error(
        &with("DataType=0x0007\nAccessType=ro\n[1000sub1]\nParameterName=x\n"),
        7,
        2,
        "sub-index of a VAR object",
    );
    assert_error(
        &with("DataType=0x0007\nAccessType=ro\n   just text\n"),
        7,
        4,
        "expected `key=value`",
    );
    assert_error(
        &with("DataType=0x0007\nAccessType=ro\n[OptionalObjects]\nSupportedObjects=1\n1=zz\n"),
        9,
        3,
        "an object index like 0x1000",
    );
    assert_error(
        &with("DataType=0x0007\nAccessType=ro\n[OptionalObjects]\nSupportedObjects=x\n"),
        8,
        18,
        "SupportedObjects= in [OptionalObjects]",
    );
    assert_error(
        b"[1018sub1]\nParameterName=x\n",
        1,
        2,
        "has no object section [1018]",
    );
    assert_error(
        b"Key=value\n[FileInfo]\n",
        1,
        1,
        "before the first [section]",
    );
    assert_error(b"[FileInfo\n", 1, 1, "expected `]`");
    assert_error(b"[]\n", 1, 1, "expected a section name");
    assert_error(b"[FileInfo]\n=x\n", 2, 1, "expected a key before `=`");
    assert_error(
        b"[DeviceInfo]\nVendorNumber=0x100000000\n",
        2,
        14,
        "VendorNumber= in [DeviceInfo]: expected a 32-bit number",
    );
    assert_error(b"[DeviceInfo]\nLSS_Supported=yes\n", 2, 15, "0 or 1");
    assert_error(
        b"[Comments]\nLines=2\nLine1=only one\n",
        1,
        2,
        "[Comments] has no Line2=",
    );
    assert_error(
        b"[DeviceComissioning]\nNodeID=five\n",
        2,
        8,
        "NodeID= in [DeviceComissioning]: expected a node-ID, 1 to 127, found `five`",
    );
}

#[test]
fn error_columns_count_characters() {
    // UTF-8 and Latin-1 spell the same characters with different byte counts; the column is the same.
    assert_error("[µµ] x\n".as_bytes(), 1, 6, "unexpected text `x`");
    assert_error(b"[\xB5\xB5] x\n", 1, 6, "unexpected text `x`");
    // A byte-order mark is not a column.
    assert_error("\u{FEFF}garbage\n".as_bytes(), 1, 1, "expected `key=value`");
    assert_error(b"[FileInfo]\r\nx\r\n", 2, 1, "found `x`");
}

/// EDS tells the PDO direction by the access type: an RPDO-only entry is written `rww`, a writable
/// TPDO-only entry `rwr`, and both read back with their direction.
#[test]
fn pdo_direction_travels_in_the_access_type() {
    let mut desc = DeviceDescription::default();
    desc.dictionary.insert(Object::var(
        0x7000,
        SubObject::new("Output", DataType::Unsigned16, AccessType::Ro).with_pdo(PdoMapping::Rpdo),
    ));
    desc.dictionary.insert(Object::var(
        0x6000,
        SubObject::new("Input", DataType::Unsigned16, AccessType::Rw).with_pdo(PdoMapping::Tpdo),
    ));
    let text = eds::write_eds(&desc);
    assert!(text.contains("[7000]\r\nParameterName=Output\r\nObjectType=0x7\r\nDataType=0x0006\r\nAccessType=rww\r\n"), "{text}");
    assert!(text.contains("[6000]\r\nParameterName=Input\r\nObjectType=0x7\r\nDataType=0x0006\r\nAccessType=rwr\r\n"), "{text}");
    let back = eds::read(text.as_bytes(), "dir.eds").unwrap();
    assert_eq!(
        back.dictionary.entry(0x7000, 0).unwrap().pdo,
        PdoMapping::Rpdo
    );
    assert_eq!(
        back.dictionary.entry(0x6000, 0).unwrap().pdo,
        PdoMapping::Tpdo
    );
}

/// A `$NODEID` default must fit for every node-ID: found by the round-trip fuzz target, where an EDS read
/// with node-ID 0 wrote a DCF for node 1 that did not read back. One that does not is dropped with a
/// warning, as python-canopen drops a default it cannot use.
#[test]
fn node_id_defaults_must_fit_for_node_127() {
    let text =
        "[1000]\nParameterName=x\nDataType=7\nAccessType=ro\nDefaultValue=$NODEID+0xFFFFFFFF\n";
    let dev = assert_warnings(
        text.as_bytes(),
        &["5:14: DefaultValue= in [1000]: with node-ID 127 the value does not fit: 4294967422 does not fit in UNSIGNED32, 0 to 4294967295; the default is dropped"],
    );
    assert_eq!(dev.dictionary.entry(0x1000, 0).unwrap().default, None);
    assert_eq!(dev.dictionary.entry(0x1000, 0).unwrap().value, [0; 4]);
    let ok =
        "[1000]\nParameterName=x\nDataType=7\nAccessType=ro\nDefaultValue=$NODEID+0xFFFFFF80\n";
    let mut dev = eds::read(ok.as_bytes(), "n.eds").unwrap();
    dev.set_node_id(Some(1));
    let dcf = eds::read(eds::write_dcf(&dev).as_bytes(), "n.dcf").unwrap();
    assert_eq!(
        dcf.dictionary.read_value(0x1000, 0).unwrap(),
        Value::Uint(0xFFFF_FF81)
    );
}
