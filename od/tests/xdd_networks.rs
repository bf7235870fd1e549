//! XDD files of other networks: a POWERLINK description (EPSG DS 311) has its object dictionary read,
//! with a warning that says what the file is; a profile body of a network the reader does not know is
//! refused, never read as a CANopen device with no objects.

use od::object::{AccessType, ObjectKind};
use od::types::DataType;
use od::value::Value;
use od::Severity;

/// A POWERLINK controlled node as openCONFIGURATOR writes one: the device body at line 3, the object
/// list in `ObjectList/Object/SubObject`, an IP_ADDRESS (0x0402) and a MAC_ADDRESS (0x0401) entry at
/// lines 10 and 11 (their `dataType` values at columns 74 and 68).
const POWERLINK: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<ISO15745ProfileContainer xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"><ISO15745Profile>
  <ProfileBody xsi:type="ProfileBody_Device_Powerlink" fileName="cn.xdd" fileVersion="01.00">
    <DeviceIdentity><vendorName>V</vendorName><productName>CN</productName></DeviceIdentity>
  </ProfileBody></ISO15745Profile><ISO15745Profile>
  <ProfileBody xsi:type="ProfileBody_CommunicationNetwork_Powerlink"><ApplicationLayers><ObjectList>
    <Object index="1000" name="NMT_DeviceType_U32" objectType="7" dataType="0007" accessType="const" defaultValue="0x000F0191"/>
    <Object index="1E40" name="NWL_IpAddrTable_0h_REC" objectType="9">
      <SubObject subIndex="00" name="NumberOfEntries" objectType="7" dataType="0005" accessType="const" defaultValue="2"/>
      <SubObject subIndex="01" name="Addr_IPAD" objectType="7" dataType="0402" accessType="rw" defaultValue="0xC0A86401"/>
      <SubObject subIndex="02" name="Mac" objectType="7" dataType="0401" accessType="ro"/>
    </Object>
  </ObjectList></ApplicationLayers></ProfileBody>
</ISO15745Profile></ISO15745ProfileContainer>
"#;

#[test]
fn a_powerlink_description_has_its_dictionary_read_and_says_what_it_is() {
    let reading = od::xdd::read_file(POWERLINK.as_bytes(), "cn.xdd").unwrap();
    let got: Vec<String> = reading
        .findings
        .iter()
        .map(|f| {
            assert_eq!(f.severity, Severity::Warning);
            let p = f.position.unwrap();
            format!("{}:{}: {}", p.line, p.column, f.message)
        })
        .collect();
    assert_eq!(
        got,
        [
            "3:3: a POWERLINK description (ProfileBody_Device_Powerlink, EPSG DS 311), not a CANopen one: its object dictionary is read; its POWERLINK network parts are not",
            "10:74: dataType 0402 of 0x1E40:01 is the POWERLINK IP_ADDRESS (4 octets); the entry is read as UNSIGNED32",
            "11:68: dataType 0401 of 0x1E40:02 is the POWERLINK MAC_ADDRESS (6 octets); the entry is read as OCTET_STRING",
        ]
    );
    let desc = &reading.devices[0];
    assert_eq!(desc.identity.product_name, "CN");
    assert_eq!(desc.can, None, "no CANopen communication profile");
    let d = &desc.dictionary;
    assert_eq!(d.len(), 2);
    let device_type = d.entry(0x1000, 0).unwrap();
    assert_eq!(device_type.access.kind, AccessType::Const);
    assert_eq!(device_type.current(), Some(Value::Uint(0x000F_0191)));
    let table = d.object(0x1E40).unwrap();
    assert_eq!(table.kind, ObjectKind::Record);
    let ip = d.entry(0x1E40, 1).unwrap();
    assert_eq!(ip.data_type, DataType::Unsigned32);
    assert_eq!(ip.value, [0x01, 0x64, 0xA8, 0xC0]);
    let mac = d.entry(0x1E40, 2).unwrap();
    assert_eq!(mac.data_type, DataType::OctetString);
    assert_eq!(mac.bit_size, Some(48));
    // Written as a (CANopen) XDD and read back: the same dictionary.
    let back = od::xdd::read(od::xdd::write(desc).as_bytes(), "back.xdd").unwrap();
    assert_eq!(od::diff::diff(&desc.dictionary, &back.dictionary), []);
}

#[test]
fn a_body_of_an_unknown_network_is_refused_with_its_kind() {
    let text = r#"<?xml version="1.0"?>
<ISO15745ProfileContainer xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"><ISO15745Profile>
  <ProfileBody xsi:type="ProfileBody_Device_Modbus"><DeviceIdentity/></ProfileBody>
</ISO15745Profile></ISO15745ProfileContainer>
"#;
    let err = od::xdd::read(text.as_bytes(), "m.xdd").unwrap_err();
    assert_eq!((err.position.line, err.position.column), (3, 3));
    assert_eq!(
        err.message,
        "a ProfileBody_Device_Modbus profile body: the file describes a device of another network, not a CANopen device (no ProfileBody_Device_CANopen or ProfileBody_CommunicationNetwork_CANopen)"
    );
}

/// A description without CAN information (a POWERLINK or EtherCAT one) is written as an XDD without
/// the CAN parts (dummy usage, physical layer, network management), and reads back without them; one
/// with CAN information keeps them.
#[test]
fn the_can_parts_are_written_only_for_a_description_that_has_them() {
    let mut desc = od::xdd::read(POWERLINK.as_bytes(), "cn.xdd").unwrap();
    // An XDD has a creation date (a required attribute); a description without one is written with
    // 1970-01-01.
    desc.file_info.creation_date = "2024-05-06".into();
    let text = od::xdd::write(&desc);
    for part in ["dummyUsage", "TransportLayers", "NetworkManagement"] {
        assert!(!text.contains(part), "{part}\n{text}");
    }
    let back = od::xdd::read(text.as_bytes(), "again.xdd").unwrap();
    assert_eq!(od::diff::diff_devices(&desc, &back), vec![]);

    let mut with_can = desc.clone();
    with_can.can = Some(od::device::CanInfo {
        baud_rates: vec![250],
        nr_of_rx_pdo: 1,
        ..Default::default()
    });
    let text = od::xdd::write(&with_can);
    assert!(
        text.contains("<supportedBaudRate value=\"250 Kbps\"/>"),
        "{text}"
    );
    let back = od::xdd::read(text.as_bytes(), "again.xdd").unwrap();
    assert_eq!(back.can, with_can.can);

    // Commissioning values without CAN information: the network management they belong in needs its
    // general features, which are written as CAN information's defaults.
    let mut configured = desc.clone();
    configured.set_node_id(Some(3));
    let back = od::xdd::read(od::xdd::write(&configured).as_bytes(), "again.xdd").unwrap();
    assert_eq!(back.node_id(), Some(3));
    assert_eq!(back.can, Some(od::device::CanInfo::default()));
}

/// A CANopen file is read from `CANopenObjectList` only: a POWERLINK `ObjectList` in it (an editor's
/// leftover) is not read, and a CANopen body beside another network's is no error.
#[test]
fn only_a_powerlink_file_has_its_object_list_read() {
    let text = r#"<?xml version="1.0"?>
<ISO15745ProfileContainer xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"><ISO15745Profile>
  <ProfileBody xsi:type="ProfileBody_Device_Modbus"><DeviceIdentity/></ProfileBody>
  <ProfileBody xsi:type="ProfileBody_CommunicationNetwork_CANopen"><ApplicationLayers>
    <CANopenObjectList>
      <CANopenObject index="1000" name="Device type" objectType="7" dataType="0007" accessType="ro"/>
    </CANopenObjectList>
    <ObjectList>
      <Object index="2000" name="Stray" objectType="7" dataType="0007" accessType="rw"/>
      <CANopenObject index="2001" name="Stray too" objectType="7" dataType="0007" accessType="rw"/>
    </ObjectList>
  </ApplicationLayers></ProfileBody>
</ISO15745Profile></ISO15745ProfileContainer>
"#;
    let reading = od::xdd::read_file(text.as_bytes(), "c.xdd").unwrap();
    let d = &reading.devices[0].dictionary;
    assert_eq!(d.objects().map(|o| o.index).collect::<Vec<_>>(), [0x1000]);
    assert_eq!(reading.findings, vec![]);
}
