use super::*;
use crate::object::{DefaultValue, ObjectKind};
use crate::value::Value;

fn wrap(network: &str, device: &str) -> String {
    format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<ISO15745ProfileContainer xmlns="http://www.canopen.org/xml/1.0" xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">
<ISO15745Profile>
<ProfileBody xsi:type="ProfileBody_Device_CANopen" fileName="t.xdd" fileCreator="me" fileCreationDate="2024-01-02" fileVersion="3">
{device}
</ProfileBody>
</ISO15745Profile>
<ISO15745Profile>
<ProfileBody xsi:type="ProfileBody_CommunicationNetwork_CANopen" fileName="t.xdd">
<ApplicationLayers>
<CANopenObjectList>
{network}
</CANopenObjectList>
</ApplicationLayers>
</ProfileBody>
</ISO15745Profile>
</ISO15745ProfileContainer>
"#
    )
}

fn err_of(text: &str) -> ParseError {
    read(text.as_bytes(), "t.xdd").unwrap_err()
}

/// A `$NODEID` default must fit for node 127; one that does not is dropped with a warning.
#[test]
fn node_id_defaults_must_fit_for_node_127() {
    let text = wrap(
        r#"<CANopenObject index="1014" name="COB-ID EMCY" objectType="7" dataType="0007" accessType="rw" defaultValue="$NODEID+0xFFFFFFFF" PDOmapping="no"/>"#,
        "",
    );
    let reading = read_file(text.as_bytes(), "t.xdd").unwrap();
    let messages: Vec<&str> = reading
        .findings
        .iter()
        .map(|f| f.message.as_str())
        .collect();
    assert_eq!(
        messages,
        ["defaultValue of 0x1014:00 (UNSIGNED32): `$NODEID+0xFFFFFFFF` does not fit with node-ID \
          127; the default is dropped"]
    );
    let d = &reading.devices[0];
    assert_eq!(d.dictionary.entry(0x1014, 0).unwrap().default, None);
}

#[test]
fn inline_objects() {
    let text = wrap(
            r#"<CANopenObject index="1014" name="COB-ID EMCY" objectType="7" dataType="0007" accessType="rw" defaultValue="$NODEID+0x80" PDOmapping="no"/>
<CANopenObject index="2000" name="Speed" objectType="7" dataType="0003" accessType="rww" defaultValue="-5" lowLimit="-100" highLimit="0x64" PDOmapping="RPDO"/>
<CANopenObject index="1018" name="Identity" objectType="9" subNumber="2">
  <CANopenSubObject subIndex="00" name="Highest sub-index supported" objectType="7" dataType="0005" accessType="ro" defaultValue="1"/>
  <CANopenSubObject subIndex="01" name="Vendor-ID" objectType="7" dataType="0007" accessType="ro" defaultValue="0x12E" PDOmapping="optional"/>
</CANopenObject>"#,
            "<DeviceIdentity><vendorName>B&amp;R</vendorName><productName>P</productName><orderNumber>X-1</orderNumber></DeviceIdentity>",
        );
    let d = read(text.as_bytes(), "t.xdd").unwrap();
    assert_eq!(d.dictionary.len(), 3);
    let emcy = d.dictionary.entry(0x1014, 0).unwrap();
    assert_eq!(
        emcy.default,
        Some(DefaultValue {
            value: Value::Uint(0x80),
            plus_node_id: true
        })
    );
    assert_eq!(emcy.access.kind, AccessType::Rw);
    assert_eq!(emcy.value, vec![0x80, 0, 0, 0]);
    let speed = d.dictionary.entry(0x2000, 0).unwrap();
    assert_eq!(speed.data_type, DataType::Integer16);
    assert_eq!(speed.default, Some(DefaultValue::plain(Value::Int(-5))));
    assert_eq!(speed.low, Some(Value::Int(-100)));
    assert_eq!(speed.high, Some(Value::Int(100)));
    assert_eq!(speed.pdo, PdoMapping::Rpdo);
    assert_eq!(speed.access.kind, AccessType::Rww);
    assert_eq!(speed.value, (-5i16).to_le_bytes());
    let id = d.dictionary.object(0x1018).unwrap();
    assert_eq!(id.kind, ObjectKind::Record);
    assert_eq!(id.subs.len(), 2);
    assert_eq!(id.subs[&1].pdo, PdoMapping::Both);
    assert_eq!(d.identity.vendor_name, "B&R");
    assert_eq!(d.identity.vendor_id, 0x12E, "from 0x1018:01");
    assert_eq!(d.identity.order_code, "X-1");
    assert_eq!(d.file_info.file_name, "t.xdd");
    assert_eq!(d.file_info.created_by, "me");
    assert_eq!(d.file_info.creation_date, "2024-01-02");
    assert_eq!(d.file_info.file_version, "3");
    assert_eq!(d.can, None, "a network body without CAN parts");
}

#[test]
fn parameters_by_unique_id_in_either_order_with_prefixes() {
    let network = r#"<ISO15745Profile>
<ProfileBody xmlns:q2="http://www.canopen.org/xml/1.1" xsi:type="q2:ProfileBody_CommunicationNetwork_CANopen">
<ApplicationLayers><q2:CANopenObjectList>
<CANopenObject index="2100" name="Errors" objectType="7" PDOmapping="no" uniqueIDRef="UID_OBJ_2100"/>
<CANopenObject index="2101" name="Mode" objectType="7" accessType="ro" defaultValue="3" uniqueIDRef="UID_OBJ_2101"/>
<CANopenObject index="6000" name="Inputs" objectType="8" uniqueIDRef="UID_OBJ_6000" subNumber="2">
  <CANopenSubObject subIndex="00" name="Highest sub-index supported" objectType="7" uniqueIDRef="UID_SUB_600000"/>
  <CANopenSubObject subIndex="01" name="Input" objectType="7" PDOmapping="TPDO" uniqueIDRef="UID_SUB_600001"/>
</CANopenObject>
<CANopenObject index="2122" name="Demo domain" objectType="7" uniqueIDRef="UID_OBJ_2122"/>
</q2:CANopenObjectList></ApplicationLayers>
</ProfileBody></ISO15745Profile>"#;
    let device = r#"<ISO15745Profile>
<ProfileBody xmlns:q1="http://www.canopen.org/xml/1.1" xsi:type="q1:ProfileBody_Device_CANopen" fileName="p.xdd">
<q1:DeviceIdentity><q1:vendorName>V</q1:vendorName><q1:vendorID>0x5</q1:vendorID><q1:productID>7</q1:productID>
<q1:productText><description lang="de">Gerät</description><description lang="en">Device</description></q1:productText>
<q1:version versionType="SW">1.0</q1:version></q1:DeviceIdentity>
<q1:ApplicationProcess>
<q1:dataTypeList>
  <q1:array name="Inputs type" uniqueID="UID_ARR_6000"><q1:subrange lowerLimit="0" upperLimit="1"/><USINT/></q1:array>
</q1:dataTypeList>
<q1:parameterList>
  <q1:parameter uniqueID="UID_OBJ_2100" access="readWrite"><description lang="en">Error bits
second line</description><BITSTRING/><q1:defaultValue value="00 01"/></q1:parameter>
  <q1:parameter uniqueID="UID_OBJ_2101" access="readWrite"><label lang="en">Mode</label><UINT/><q1:defaultValue value="9"/>
    <q1:allowedValues><q1:range><q1:minValue value="1"/><q1:maxValue value="5"/></q1:range></q1:allowedValues></q1:parameter>
  <q1:parameter uniqueID="UID_OBJ_6000"><description lang="en">Digital inputs.</description><q1:dataTypeIDRef uniqueIDRef="UID_ARR_6000"/></q1:parameter>
  <q1:parameter uniqueID="UID_SUB_600000"><label lang="en">Highest sub-index supported</label><USINT/><q1:defaultValue value="0x01"/></q1:parameter>
  <q1:parameter uniqueID="UID_SUB_600001"><label lang="en">Input 1 of 8</label><q1:defaultValue value="0"/></q1:parameter>
  <q1:parameter uniqueID="UID_OBJ_2122" access="readWrite"><label lang="en">Demo domain</label><BITSTRING/></q1:parameter>
</q1:parameterList>
</q1:ApplicationProcess>
</ProfileBody></ISO15745Profile>"#;
    for (first, second) in [(network, device), (device, network)] {
        let text = format!(
                "<?xml version=\"1.1\" encoding=\"utf-8\"?>\n<ISO15745ProfileContainer xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\">{first}{second}</ISO15745ProfileContainer>"
            );
        let d = read(text.as_bytes(), "p.xdd").unwrap();
        assert_eq!(d.identity.vendor_id, 5);
        assert_eq!(d.identity.product_code, 7);
        assert_eq!(d.file_info.description, "Device");
        assert_eq!(d.file_info.file_name, "p.xdd");
        let errors = d.dictionary.object(0x2100).unwrap();
        assert_eq!(
            errors.description.as_deref(),
            Some("Error bits\nsecond line")
        );
        assert_eq!(errors.subs[&0].description, errors.description);
        let e = &errors.subs[&0];
        assert_eq!(e.data_type, DataType::OctetString);
        assert_eq!(e.access.kind, AccessType::Rw);
        assert_eq!(e.value, vec![0, 1]);
        let mode = d.dictionary.entry(0x2101, 0).unwrap();
        assert_eq!(mode.data_type, DataType::Unsigned16);
        assert_eq!(mode.access.kind, AccessType::Ro, "inline accessType wins");
        assert_eq!(
            mode.default,
            Some(DefaultValue::plain(Value::Uint(3))),
            "inline default wins"
        );
        assert_eq!(mode.low, Some(Value::Uint(1)));
        assert_eq!(mode.high, Some(Value::Uint(5)));
        assert_eq!(
            mode.description, None,
            "a label equal to the name is no description"
        );
        let inputs = d.dictionary.object(0x6000).unwrap();
        assert_eq!(inputs.type_name.as_deref(), Some("Inputs type"));
        assert_eq!(inputs.description.as_deref(), Some("Digital inputs."));
        assert_eq!(
            inputs.subs[&1].data_type,
            DataType::Unsigned8,
            "element type of the array"
        );
        assert_eq!(inputs.subs[&1].pdo, PdoMapping::Tpdo);
        assert_eq!(inputs.subs[&1].description.as_deref(), Some("Input 1 of 8"));
        assert_eq!(
            inputs.subs[&0].default,
            Some(DefaultValue::plain(Value::Uint(1)))
        );
        assert_eq!(inputs.subs[&0].description, None);
        let domain = d.dictionary.entry(0x2122, 0).unwrap();
        assert_eq!(
            domain.data_type,
            DataType::Domain,
            "BITSTRING without default"
        );
    }
}

#[test]
fn commissioning_features_and_actual_values() {
    let text = r#"<ISO15745ProfileContainer><ISO15745Profile>
<ProfileBody xsi:type="ProfileBody_CommunicationNetwork_CANopen" xmlns:xsi="x">
<ApplicationLayers>
<CANopenObjectList>
<CANopenObject index="1800" name="TPDO" objectType="9">
  <CANopenSubObject subIndex="01" name="COB-ID" objectType="7" dataType="0007" accessType="rw" defaultValue="$NODEID+0x180" actualValue="0x00000190"/>
  <CANopenSubObject subIndex="02" name="Type" objectType="7" dataType="0005" accessType="rw" defaultValue="0xFF"/>
</CANopenObject>
</CANopenObjectList>
<dummyUsage><dummy entry="Dummy0001=0"/><dummy entry="Dummy0007=1"/><dummy entry="Dummy0005=1"/></dummyUsage>
</ApplicationLayers>
<TransportLayers><PhysicalLayer><baudRate defaultValue="250 Kbps"><supportedBaudRate value="500 Kbps"/><supportedBaudRate value="125 Kbps"/><supportedBaudRate value="auto-baudRate"/></baudRate></PhysicalLayer></TransportLayers>
<NetworkManagement>
<CANopenGeneralFeatures granularity="0" nrOfRxPDO="2" nrOfTxPDO="3" bootUpSlave="true" groupMessaging="1" dynamicChannels="1" layerSettingServiceSlave="false" selfStartingDevice="true"/>
<CANopenMasterFeatures bootUpMaster="true"/>
<deviceCommissioning nodeID="5" nodeName="axis" actualBaudRate="500 Kbps" networkNumber="2" networkName="line" CANopenManager="false"/>
</NetworkManagement>
</ProfileBody></ISO15745Profile></ISO15745ProfileContainer>"#;
    let d = read(text.as_bytes(), "t.xdc").unwrap();
    let can = d.can.as_ref().unwrap();
    assert_eq!(can.baud_rates, vec![125, 500]);
    assert_eq!(can.dummy_usage, vec![5, 7]);
    assert_eq!(can.granularity, 0);
    assert_eq!((can.nr_of_rx_pdo, can.nr_of_tx_pdo), (2, 3));
    assert!(can.simple_boot_up_slave && can.group_messaging && can.simple_boot_up_master);
    assert!(!can.lss_supported);
    assert_eq!(can.dynamic_channels, 1);
    let c = d.commissioning.as_ref().unwrap();
    assert_eq!(c.node_id, Some(5));
    assert_eq!(c.node_name, "axis");
    assert_eq!(c.baud_rate, 500);
    assert_eq!(c.net_number, 2);
    assert_eq!(c.network_name, "line");
    let cob = d.dictionary.entry(0x1800, 1).unwrap();
    assert!(cob.value_set);
    assert_eq!(cob.value, 0x190u32.to_le_bytes());
    let tt = d.dictionary.entry(0x1800, 2).unwrap();
    assert!(!tt.value_set);
    assert_eq!(tt.value, vec![0xFF]);
}

#[test]
fn a_parameter_refines_rw_into_rwr_or_rww_but_does_not_override_the_object() {
    let text = wrap(
        r#"<CANopenObject index="2000" name="Out" objectType="7" dataType="0006" accessType="rw" PDOmapping="RPDO" uniqueIDRef="A"/>
<CANopenObject index="2001" name="In" objectType="7" dataType="0006" accessType="rw" PDOmapping="TPDO" uniqueIDRef="B"/>
<CANopenObject index="2002" name="Plain" objectType="7" dataType="0006" accessType="rw" uniqueIDRef="C"/>
<CANopenObject index="2003" name="Ro" objectType="7" dataType="0006" accessType="ro" uniqueIDRef="A"/>
<CANopenObject index="2004" name="Hand-written" objectType="7" dataType="0006" accessType="rww"/>"#,
        r#"<ApplicationProcess><parameterList>
<parameter uniqueID="A" access="readWriteOutput"><label>x</label><UINT/></parameter>
<parameter uniqueID="B" access="readWriteInput"><label>x</label><UINT/></parameter>
<parameter uniqueID="C" access="read"><label>x</label><UINT/></parameter>
</parameterList></ApplicationProcess>"#,
    );
    let d = read(text.as_bytes(), "t.xdd").unwrap();
    let access = |i| d.dictionary.entry(i, 0).unwrap().access.kind;
    assert_eq!(access(0x2000), AccessType::Rww);
    assert_eq!(access(0x2001), AccessType::Rwr);
    assert_eq!(access(0x2002), AccessType::Rw);
    assert_eq!(access(0x2003), AccessType::Ro);
    assert_eq!(access(0x2004), AccessType::Rww);
}

#[test]
fn canopen_editor_spells_node_id_with_a_capital() {
    let text = r#"<ISO15745ProfileContainer><ISO15745Profile><ProfileBody>
<NetworkManagement><deviceCommissioning NodeID="9" nodeName="n" actualBaudRate="125 Kbps" networkNumber="1" networkName="x" CANopenManager="true"/></NetworkManagement>
</ProfileBody></ISO15745Profile></ISO15745ProfileContainer>"#;
    let d = read(text.as_bytes(), "t.xdc").unwrap();
    let c = d.commissioning.unwrap();
    assert_eq!(
        (c.node_id, c.baud_rate, c.canopen_manager),
        (Some(9), 125, true)
    );
    let e = err_of(&text.replace("NodeID=\"9\" ", ""));
    assert_eq!(e.position.line, 2, "{e}");
    assert!(e.message.contains("nodeID"), "{e}");
    let e = err_of(&text.replace("NodeID=\"9\"", "nodeID=\"128\""));
    assert!(e.message.contains("1 to 127"), "{e}");
}

#[test]
fn node_id_spellings() {
    assert_eq!(strip_node_id("$NODEID+0x180"), Some("0x180"));
    assert_eq!(strip_node_id(" $nodeid + 0x80 "), Some("0x80"));
    assert_eq!(strip_node_id("0x600+$NODEID"), Some("0x600"));
    assert_eq!(strip_node_id("$NODEID"), Some(""));
    assert_eq!(strip_node_id("0x180"), None);
    assert_eq!(strip_node_id("€"), None);
}

#[test]
fn errors_name_line_and_column() {
    let text = wrap(
        r#"<CANopenObject index="1000" name="A" objectType="7" dataType="0007" defaultValue="zz"/>"#,
        "",
    );
    // A default that is no value of its type is no error: it is dropped, with a warning there.
    let reading = read_file(text.as_bytes(), "t.xdd").unwrap();
    let w = &reading.findings[0];
    let at = w.position.expect("a position");
    assert_eq!((at.line, at.column), (12, 83), "{}", w.message);
    assert!(
        w.message.contains("UNSIGNED32")
            && w.message.contains("`zz`")
            && w.message.ends_with("; the default is dropped"),
        "{}",
        w.message
    );

    let e = err_of(&wrap(
        r#"<CANopenObject index="10G0" name="A" objectType="7"/>"#,
        "",
    ));
    assert_eq!((e.position.line, e.position.column), (12, 23), "{e}");
    assert!(e.message.contains("index"), "{e}");

    let e = err_of(&wrap(
        r#"<CANopenObject index="1000" name="A" objectType="7" dataType="0007" accessType="readonly"/>"#,
        "",
    ));
    assert_eq!((e.position.line, e.position.column), (12, 81), "{e}");

    let e = err_of(&wrap(
        r#"  <CANopenObject index="1000" name="A" objectType="7"/>"#,
        "",
    ));
    assert_eq!((e.position.line, e.position.column), (12, 3), "{e}");
    assert!(e.message.contains("no data type"), "{e}");

    let e = err_of(&wrap(
        r#"<CANopenObject index="1000" name="A" objectType="7" uniqueIDRef="nope"/>"#,
        "",
    ));
    assert_eq!((e.position.line, e.position.column), (12, 66), "{e}");
    assert!(e.message.contains("`nope`"), "{e}");

    let e = err_of(&wrap(
        r#"<CANopenObject index="1000" name="A" objectType="7" dataType="0007"/>
<CANopenObject index="1000" name="B" objectType="7" dataType="0007"/>"#,
        "",
    ));
    assert_eq!((e.position.line, e.position.column), (13, 1), "{e}");

    // A complex type is no error: a DOMAIN, with a warning at the attribute's value.
    let text = wrap(
        r#"<CANopenObject index="1000" name="A" objectType="7" dataType="0020"/>"#,
        "",
    );
    let r = read_file(text.as_bytes(), "t.xdd").unwrap();
    let w = &r.findings[0];
    assert_eq!(
        w.position,
        Some(Position {
            line: 12,
            column: 63
        })
    );
    assert_eq!(
        w.message,
        "dataType 0020 of 0x1000:00 is a complex or profile data type; the entry is read as DOMAIN"
    );
    assert_eq!(
        r.devices[0].dictionary.entry(0x1000, 0).unwrap().data_type,
        DataType::Domain
    );

    let e = err_of(&wrap(
        r#"<CANopenObject index="1000" name="A" objectType="7" dataType="0007" PDOmapping="yes"/>"#,
        "",
    ));
    assert_eq!((e.position.line, e.position.column), (12, 81), "{e}");

    let e = err_of(&wrap(
        "",
        r#"<DeviceIdentity><vendorID>12x</vendorID></DeviceIdentity>"#,
    ));
    assert_eq!(e.position.line, 5, "{e}");
    assert!(e.message.contains("vendorID"), "{e}");

    let e = err_of("<?xml version=\"1.0\"?>\n<EtherCATInfo/>");
    assert_eq!((e.position.line, e.position.column), (2, 1), "{e}");
    assert!(e.message.contains("ISO15745ProfileContainer"), "{e}");

    let e = err_of("<ISO15745ProfileContainer>\n  <a></b>\n</ISO15745ProfileContainer>");
    assert_eq!(e.position.line, 2, "{e}");

    let e = err_of("<ISO15745ProfileContainer>\n  <a>");
    assert!(e.message.contains("end of file"), "{e}");
    let e = err_of("");
    assert!(e.message.contains("ISO15745ProfileContainer"), "{e}");
}

#[test]
fn line_ends_and_references_in_text_and_attributes() {
    let text = wrap(
            "<CANopenObject index=\"2000\" name=\"a&#10;b\tc\r\nd\" objectType=\"7\" dataType=\"0009\" defaultValue=\"x&#9;&lt;&#x20AC;\" uniqueIDRef=\"P\"/>",
            "<ApplicationProcess><parameterList><parameter uniqueID=\"P\"><description>one\r\ntwo\rthree&#13;&amp;<![CDATA[<four>]]></description></parameter></parameterList></ApplicationProcess>",
        );
    let d = read(text.as_bytes(), "t.xdd").unwrap();
    let o = d.dictionary.object(0x2000).unwrap();
    assert_eq!(o.name, "a\nb c d");
    assert_eq!(o.description.as_deref(), Some("one\ntwo\nthree\r&<four>"));
    assert_eq!(
        o.subs[&0].default,
        Some(DefaultValue::plain(Value::String("x\t<€".into())))
    );
}

#[test]
fn unknown_elements_and_attributes_are_skipped() {
    let text = wrap(
            r#"<vendorThing index="zz"><CANopenObject index="zz"/></vendorThing>
<CANopenObject index="1000" name="A" objectType="7" dataType="0007" vendorAttr="?" objFlags="0001" denotation="x" subNumber="0"><extra/></CANopenObject>"#,
            "<DeviceIdentity><vendorFamily>x</vendorFamily></DeviceIdentity><foo><parameterList/></foo>",
        );
    let d = read(text.as_bytes(), "t.xdd").unwrap();
    assert_eq!(d.dictionary.len(), 1);
}

/// An XDD whose `dataTypeList` holds `types`, from line 6 (the list's own tag is on line 5), and
/// whose object list holds `objects`, from line 12 + the lines of `types`.
fn with_types(types: &str, objects: &str) -> String {
    wrap(
        objects,
        &format!(
            "<ApplicationProcess><dataTypeList>\n{types}\n</dataTypeList></ApplicationProcess>"
        ),
    )
}

/// A struct whose member is of the struct's own type: the error is at the `uniqueIDRef`'s value
/// (line 7, after the 67 characters before it).
#[test]
fn a_type_made_of_itself_is_an_error() {
    let e = err_of(&with_types(
        "<struct uniqueID=\"A\" name=\"Alpha\">\n\
         <varDeclaration uniqueID=\"A1\" name=\"x\"><dataTypeIDRef uniqueIDRef=\"A\"/></varDeclaration>\n\
         </struct>",
        "",
    ));
    assert_eq!(e.message, "data type `A` (Alpha) refers to itself");
    assert_eq!((e.position.line, e.position.column), (7, 68), "{e}");
}

/// Array A of B, struct B with a member of C, derived C of A: the way round is named from the
/// first type of the file on it, at its reference to the next (line 7, column 103); D, which only
/// leads into the circle, is not named. Types that share a part (E and F both of G, H of E and F)
/// are no circle.
#[test]
fn a_circle_of_types_is_named_with_the_way_round() {
    let circle = "<derived uniqueID=\"D\" name=\"Delta\"><dataTypeIDRef uniqueIDRef=\"A\"/></derived>\n\
         <array uniqueID=\"A\" name=\"Alpha\"><subrange lowerLimit=\"1\" upperLimit=\"4\"/><dataTypeIDRef uniqueIDRef=\"B\"/></array>\n\
         <struct uniqueID=\"B\" name=\"Beta\"><varDeclaration uniqueID=\"B1\" name=\"b\"><UINT/></varDeclaration><varDeclaration uniqueID=\"B2\" name=\"c\"><dataTypeIDRef uniqueIDRef=\"C\"/></varDeclaration></struct>\n\
         <derived uniqueID=\"C\" name=\"Gamma\"><dataTypeIDRef uniqueIDRef=\"A\"/></derived>";
    let e = err_of(&with_types(circle, ""));
    assert_eq!(
        e.message,
        "data type `A` (Alpha) refers to itself through `B` → `C`"
    );
    assert_eq!((e.position.line, e.position.column), (7, 103), "{e}");

    let shared = "<struct uniqueID=\"H\" name=\"\"><varDeclaration uniqueID=\"H1\" name=\"e\"><dataTypeIDRef uniqueIDRef=\"E\"/></varDeclaration><varDeclaration uniqueID=\"H2\" name=\"f\"><dataTypeIDRef uniqueIDRef=\"F\"/></varDeclaration></struct>\n\
         <derived uniqueID=\"E\" name=\"\"><dataTypeIDRef uniqueIDRef=\"G\"/></derived>\n\
         <array uniqueID=\"F\" name=\"\"><subrange lowerLimit=\"1\" upperLimit=\"2\"/><dataTypeIDRef uniqueIDRef=\"G\"/></array>\n\
         <derived uniqueID=\"G\" name=\"\"><UINT/></derived>";
    read(with_types(shared, "").as_bytes(), "t.xdd").unwrap();

    // A reference inside a type to no type.
    let e = err_of(&with_types(
        "<derived uniqueID=\"E\" name=\"\"><dataTypeIDRef uniqueIDRef=\"nope\"/></derived>",
        "",
    ));
    assert_eq!(
        e.message,
        "dataTypeIDRef `nope` names no type of the dataTypeList"
    );
    assert_eq!((e.position.line, e.position.column), (6, 59), "{e}");
}

/// 20,000 types each of the next: read without a call per type on the stack. With the last of
/// the first, the circle is named by its first four types after T0 and its last.
#[test]
fn a_long_chain_of_types_reads_and_its_circle_is_named_short() {
    let chain = |last: &str| {
        let mut t = String::new();
        for k in 0..20_000 {
            let next = if k == 19_999 {
                last.to_string()
            } else {
                format!("<dataTypeIDRef uniqueIDRef=\"T{}\"/>", k + 1)
            };
            t.push_str(&format!(
                "<derived uniqueID=\"T{k}\" name=\"\">{next}</derived>\n"
            ));
        }
        with_types(&t, "")
    };
    read(chain("<UINT/>").as_bytes(), "t.xdd").unwrap();
    let e = err_of(&chain("<dataTypeIDRef uniqueIDRef=\"T0\"/>"));
    assert_eq!(
        e.message,
        "data type `T0` refers to itself through `T1` → `T2` → `T3` → `T4` → … (19994 more) → `T19999`"
    );
    assert_eq!((e.position.line, e.position.column), (6, 60), "{e}");
}

/// An array's subrange is an ARRAY's sub-indices: 0 to 254 (CANopenEditor's, sub-index 0 among
/// them) and 1 to 254 read; 1 to 2^32−1, 0 to 255 and −1 to 3 are errors at the limit out of
/// 0x00–0xFE; a limit that is no number is named. Nothing is made per element: 2^32−1 of them
/// are refused at once.
#[test]
fn an_array_no_device_holds_is_an_error() {
    let array = |low: &str, high: &str| {
        format!(
            "<array uniqueID=\"BIG\" name=\"Big\"><subrange lowerLimit=\"{low}\" upperLimit=\"{high}\"/><UDINT/></array>"
        )
    };
    read(
        with_types(
            &format!(
                "{}\n{}",
                array("0", "254"),
                array("1", "254").replace("BIG", "B2")
            ),
            "",
        )
        .as_bytes(),
        "t.xdd",
    )
    .unwrap();
    let e = err_of(&with_types(&array("1", "4294967295"), ""));
    assert_eq!(
        e.message,
        "array `BIG` (Big) has elements 1 to 4294967295 (subrange): no ARRAY holds them, CiA 301 \
         sub-indices go to 0xFE"
    );
    // `<array uniqueID="BIG" name="Big"><subrange lowerLimit="1" upperLimit="`: 70 characters.
    assert_eq!((e.position.line, e.position.column), (6, 71), "{e}");
    let e = err_of(&with_types(&array("0", "255"), ""));
    assert!(
        e.message
            .starts_with("array `BIG` (Big) has elements 0 to 255 "),
        "{e}"
    );
    let e = err_of(&with_types(&array("-1", "3"), ""));
    assert!(
        e.message
            .starts_with("array `BIG` (Big) has elements -1 to 3 "),
        "{e}"
    );
    assert_eq!((e.position.line, e.position.column), (6, 56), "{e}");
    let e = err_of(&with_types(&array("1", "lots"), ""));
    assert_eq!(
        e.message,
        "expected a number like 8 in upperLimit, found `lots`"
    );
}

/// A struct of 255 members (sub-indices 0x00–0xFE) reads; one of 256 is an error at its
/// `uniqueID`. An object's subNumber of 256 (every sub-index, 0xFF's structure entry too) reads,
/// of 257 or 2^32−1 is an error at its value.
#[test]
fn a_record_or_object_of_more_sub_indices_than_there_are_is_an_error() {
    let members = |n: usize| {
        let mut t = String::from("<struct uniqueID=\"S\" name=\"Many\">");
        for k in 0..n {
            t.push_str(&format!(
                "<varDeclaration uniqueID=\"S{k}\" name=\"m\"><USINT/></varDeclaration>"
            ));
        }
        t + "</struct>"
    };
    read(with_types(&members(255), "").as_bytes(), "t.xdd").unwrap();
    let e = err_of(&with_types(&members(256), ""));
    assert_eq!(
        e.message,
        "struct `S` (Many) has 256 members: no RECORD holds them, CiA 301 sub-indices go to 0xFE"
    );
    assert_eq!((e.position.line, e.position.column), (6, 19), "{e}");

    let object = |n: &str| {
        wrap(
            &format!(
                "<CANopenObject index=\"2000\" name=\"A\" objectType=\"8\" subNumber=\"{n}\">\n\
                 <CANopenSubObject subIndex=\"00\" name=\"n\" objectType=\"7\" dataType=\"0005\" accessType=\"ro\"/>\n\
                 </CANopenObject>"
            ),
            "",
        )
    };
    read(object("256").as_bytes(), "t.xdd").unwrap();
    for n in ["257", "4294967295"] {
        let e = err_of(&object(n));
        assert_eq!(
            e.message,
            format!(
                "object 0x2000 declares {n} sub-objects (subNumber): no object holds them, \
                 sub-indices go to 0xFF"
            )
        );
        assert_eq!((e.position.line, e.position.column), (12, 64), "{e}");
    }
}

/// `DeviceIdentity/version`: the first of each type, HW, SW and FW; the writer writes them back
/// after the order number.
#[test]
fn versions_of_the_device_identity() {
    let identity = |versions: &str| {
        let text = wrap(
            "",
            &format!(
                "<DeviceIdentity><productName>P</productName><orderNumber>X-1</orderNumber>{versions}</DeviceIdentity>"
            ),
        );
        read(text.as_bytes(), "t.xdd").unwrap().identity
    };
    let id = identity(
        r#"<version versionType="FW">fw 2</version><version versionType="HW"> B </version><version versionType="SW">1.4</version><version versionType="SW">9</version>"#,
    );
    assert_eq!(id.hardware_version, "B");
    assert_eq!(id.software_version, "1.4");
    assert_eq!(id.firmware_version, "fw 2");
    let id = identity(r#"<version versionType="FW">fw 2</version><version>untyped</version>"#);
    assert_eq!(id.hardware_version, "");
    assert_eq!(id.software_version, "");
    assert_eq!(id.firmware_version, "fw 2");

    let mut desc = crate::device::DeviceDescription::default();
    desc.identity.order_code = "X-1".into();
    desc.identity.hardware_version = "B".into();
    desc.identity.software_version = "1.4".into();
    desc.identity.firmware_version = "fw 2".into();
    let written = crate::xdd::write(&desc);
    assert!(
        written.contains(
            "<orderNumber>X-1</orderNumber>\n        <version versionType=\"HW\">B</version>\n        <version versionType=\"SW\">1.4</version>\n        <version versionType=\"FW\">fw 2</version>\n"
        ),
        "{written}"
    );
    let back = read(written.as_bytes(), "w.xdd").unwrap();
    assert_eq!(back.identity, desc.identity);
}
