//! Element text written as CDATA (`<Name><![CDATA[Motor & Drive]]></Name>`, as Elmo's and Beckhoff's
//! ESI tools write names and URLs) reads as its content in every text field the ESI and XDD readers
//! take, and so does text mixed of plain text, references and CDATA pieces (XML 1.0 §2.7).

use od::device::EsiRoot;
use od::report::Severity;
use od::value::Value;

/// One device with CDATA in each kind of text field the ESI reader takes.
const ESI: &str = r##"<?xml version="1.0" encoding="UTF-8"?>
<EtherCATInfo Version="1.11">
  <Vendor>
    <Id><![CDATA[#x00000ABC]]></Id>
    <Name LcId="1033"><![CDATA[Motors & Drives <Ltd>]]></Name>
  </Vendor>
  <Descriptions>
    <Groups>
      <Group>
        <Type><![CDATA[drives]]></Type>
        <Name LcId="1033"><![CDATA[Drives & more]]></Name>
      </Group>
    </Groups>
    <Devices>
      <Device Physics="YY">
        <Type ProductCode="#x00000001" RevisionNo="#x00000002"><![CDATA[MD-1 & co]]></Type>
        <Name LcId="1033">Motor &amp; <![CDATA[<Drive>]]> one</Name>
        <URL LcId="1033"><![CDATA[https://example.com/md?a=1&b=2]]></URL>
        <GroupType><![CDATA[drives]]></GroupType>
        <Profile>
          <Dictionary>
            <DataTypes>
              <DataType>
                <Name><![CDATA[USINT]]></Name>
                <BitSize><![CDATA[8]]></BitSize>
              </DataType>
              <DataType>
                <Name><![CDATA[STRING(5)]]></Name>
                <BitSize>40</BitSize>
              </DataType>
              <DataType>
                <Name><![CDATA[DT2000 & X]]></Name>
                <BitSize>24</BitSize>
                <Comment><![CDATA[Type & comment]]></Comment>
                <SubItem>
                  <SubIdx>0</SubIdx>
                  <Name><![CDATA[Number of entries]]></Name>
                  <Type><![CDATA[USINT]]></Type>
                  <BitSize>8</BitSize>
                  <BitOffs>0</BitOffs>
                  <Flags>
                    <Access><![CDATA[ro]]></Access>
                  </Flags>
                </SubItem>
                <SubItem>
                  <SubIdx>1</SubIdx>
                  <Name><![CDATA[Gain <1>]]></Name>
                  <Type><![CDATA[USINT]]></Type>
                  <BitSize>8</BitSize>
                  <BitOffs>16</BitOffs>
                  <Comment>Gain &lt; <![CDATA[& > ]]>factor</Comment>
                  <Flags>
                    <Access><![CDATA[rw]]></Access>
                    <PdoMapping><![CDATA[R]]></PdoMapping>
                  </Flags>
                </SubItem>
              </DataType>
            </DataTypes>
            <Objects>
              <Object>
                <Index><![CDATA[#x2000]]></Index>
                <Name><![CDATA[Record & co]]></Name>
                <Comment><![CDATA[Object & comment]]></Comment>
                <Type><![CDATA[DT2000 & X]]></Type>
                <BitSize>24</BitSize>
                <Info>
                  <SubItem>
                    <Name><![CDATA[Number of entries]]></Name>
                    <Info>
                      <DefaultValue><![CDATA[1]]></DefaultValue>
                    </Info>
                  </SubItem>
                  <SubItem>
                    <Name><![CDATA[Gain <1>]]></Name>
                    <Info>
                      <MinValue><![CDATA[2]]></MinValue>
                      <MaxValue><![CDATA[#x20]]></MaxValue>
                      <DefaultData><![CDATA[07]]></DefaultData>
                    </Info>
                  </SubItem>
                </Info>
              </Object>
              <Object>
                <Index>#x2001</Index>
                <Name>Label</Name>
                <Type><![CDATA[STRING(5)]]></Type>
                <BitSize>40</BitSize>
                <Info>
                  <DefaultString><![CDATA[a&<b>]]></DefaultString>
                </Info>
                <Flags>
                  <Access><![CDATA[rw]]></Access>
                </Flags>
              </Object>
              <Object>
                <Index><![CDATA[#x0x2002]]></Index>
                <Name>Mode</Name>
                <Type>USINT</Type>
                <BitSize>8</BitSize>
                <Info>
                  <DefaultValue>3</DefaultValue>
                </Info>
                <Flags>
                  <Access>rw</Access>
                </Flags>
              </Object>
            </Objects>
          </Dictionary>
        </Profile>
        <Fmmu><![CDATA[Outputs]]></Fmmu>
        <Sm StartAddress="#x1100" ControlByte="#x64" Enable="1"><![CDATA[Outputs]]></Sm>
        <RxPdo Fixed="1" Sm="0">
          <Index><![CDATA[#x1600]]></Index>
          <Name><![CDATA[Outputs & more]]></Name>
          <Entry>
            <Index>#x2000</Index>
            <SubIndex><![CDATA[1]]></SubIndex>
            <BitLen><![CDATA[8]]></BitLen>
            <Name><![CDATA[Gain <1>]]></Name>
            <Comment><![CDATA[Entry & comment]]></Comment>
            <DataType><![CDATA[USINT]]></DataType>
          </Entry>
        </RxPdo>
        <Mailbox>
          <CoE SdoInfo="1">
            <InitCmd>
              <Transition><![CDATA[PS]]></Transition>
              <Index>#x2000</Index>
              <SubIndex>1</SubIndex>
              <Data><![CDATA[05]]></Data>
              <Comment><![CDATA[Gain & start]]></Comment>
            </InitCmd>
          </CoE>
        </Mailbox>
        <Dc>
          <OpMode>
            <Name><![CDATA[DC & Sync]]></Name>
            <Desc><![CDATA[SYNC0 <on>]]></Desc>
            <AssignActivate><![CDATA[#x0300]]></AssignActivate>
          </OpMode>
        </Dc>
      </Device>
    </Devices>
  </Descriptions>
</EtherCATInfo>
"##;

#[test]
fn esi_text_fields_written_as_cdata_read_as_their_content() {
    let reading = od::esi::read_file(ESI.as_bytes(), "cdata.xml").unwrap_or_else(|e| panic!("{e}"));
    let d = &reading.devices[0];
    assert_eq!(d.identity.vendor_id, 0xABC);
    assert_eq!(d.identity.vendor_name, "Motors & Drives <Ltd>");
    assert_eq!(d.identity.order_code, "MD-1 & co");
    assert_eq!(d.identity.product_name, "Motor & <Drive> one");
    let ecat = d.ethercat.as_ref().unwrap();
    assert_eq!(ecat.root, EsiRoot::EtherCatInfo);
    assert_eq!(ecat.group_type, "drives");
    let record = d.dictionary.object(0x2000).unwrap();
    assert_eq!(record.name, "Record & co");
    assert_eq!(record.description.as_deref(), Some("Object & comment"));
    assert_eq!(record.type_name.as_deref(), Some("DT2000 & X"));
    let gain = d.dictionary.entry(0x2000, 1).unwrap();
    assert_eq!(gain.name, "Gain <1>");
    assert_eq!(gain.description.as_deref(), Some("Gain < & > factor"));
    assert!(gain.access.kind.writable());
    assert_eq!(d.dictionary.read_value(0x2000, 1).unwrap(), Value::Uint(7));
    assert_eq!(gain.low, Some(Value::Uint(2)));
    assert_eq!(gain.high, Some(Value::Uint(0x20)));
    assert_eq!(
        d.dictionary.read_value(0x2001, 0).unwrap(),
        Value::String("a&<b>".into())
    );
    assert_eq!(ecat.fmmus, ["Outputs"]);
    assert_eq!(ecat.sync_managers[0].kind, "Outputs");
    let pdo = &ecat.rx_pdos[0];
    assert_eq!((pdo.index, pdo.name.as_str()), (0x1600, "Outputs & more"));
    let entry = &pdo.entries[0];
    assert_eq!((entry.sub, entry.bit_len), (1, 8));
    assert_eq!(entry.name, "Gain <1>");
    assert_eq!(entry.comment, "Entry & comment");
    assert_eq!(entry.data_type, "USINT");
    let cmd = &ecat.mailbox.as_ref().unwrap().init_cmds[0];
    assert_eq!(cmd.transitions, ["PS"]);
    assert_eq!(cmd.data, [5]);
    assert_eq!(cmd.comment, "Gain & start");
    let mode = &ecat.op_modes[0];
    assert_eq!(mode.name, "DC & Sync");
    assert_eq!(mode.desc, "SYNC0 <on>");
    assert_eq!(mode.assign_activate, 0x0300);
    // A warning about a value in CDATA is at the value, inside the section.
    let warnings: Vec<String> = reading
        .findings
        .iter()
        .filter(|f| f.severity == Severity::Warning)
        .map(|f| {
            let p = f.position.unwrap();
            format!("{}:{}: {}", p.line, p.column, f.message)
        })
        .collect();
    assert_eq!(
        warnings,
        ["96:33: `#x0x2002` in <Object>/<Index> has two hexadecimal prefixes; read as #x2002"]
    );
    assert_eq!(d.dictionary.read_value(0x2002, 0).unwrap(), Value::Uint(3));
}

/// An XDD with CDATA in each text element the XDD reader takes: the identity, the product text, and
/// a parameter's label and description.
const XDD: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<ISO15745ProfileContainer xmlns="http://www.canopen.org/xml/1.0" xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">
<ISO15745Profile>
<ProfileBody xsi:type="ProfileBody_Device_CANopen" fileName="t.xdd">
<DeviceIdentity>
<vendorName><![CDATA[Motors & Drives <Ltd>]]></vendorName>
<vendorID><![CDATA[0x00000ABC]]></vendorID>
<productName>Motor &amp; <![CDATA[<Drive>]]> one</productName>
<productID><![CDATA[0x00000001]]></productID>
<version versionType="SW"><![CDATA[1.2 & 3]]></version>
<version versionType="FW"><![CDATA[<4.5>]]></version>
<version versionType="HW"><![CDATA[B&C]]></version>
<orderNumber><![CDATA[MD-1 & co]]></orderNumber>
<productText><description lang="en"><![CDATA[A drive & <its> motor
on two lines]]></description></productText>
</DeviceIdentity>
<ApplicationProcess>
<parameterList>
<parameter uniqueID="UID_OBJ_2000" access="readWrite">
<label lang="en"><![CDATA[Gain <1>]]></label>
<description lang="en">Gain &lt; <![CDATA[& > ]]>factor</description>
<USINT/>
</parameter>
<parameter uniqueID="UID_OBJ_2001" access="readWrite">
<label lang="en"><![CDATA[Offset & bias]]></label>
<INT/>
</parameter>
</parameterList>
</ApplicationProcess>
</ProfileBody>
</ISO15745Profile>
<ISO15745Profile>
<ProfileBody xsi:type="ProfileBody_CommunicationNetwork_CANopen" fileName="t.xdd">
<ApplicationLayers>
<CANopenObjectList>
<CANopenObject index="2000" name="Gain" objectType="7" dataType="0005" accessType="rw" defaultValue="7" uniqueIDRef="UID_OBJ_2000"/>
<CANopenObject index="2001" name="Offset" objectType="7" dataType="0003" accessType="rw" defaultValue="-2" uniqueIDRef="UID_OBJ_2001"/>
</CANopenObjectList>
</ApplicationLayers>
</ProfileBody>
</ISO15745Profile>
</ISO15745ProfileContainer>
"#;

#[test]
fn xdd_text_fields_written_as_cdata_read_as_their_content() {
    let d = od::xdd::read(XDD.as_bytes(), "cdata.xdd").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(d.identity.vendor_name, "Motors & Drives <Ltd>");
    assert_eq!(d.identity.vendor_id, 0xABC);
    assert_eq!(d.identity.product_name, "Motor & <Drive> one");
    assert_eq!(d.identity.product_code, 1);
    assert_eq!(d.identity.order_code, "MD-1 & co");
    assert_eq!(d.identity.software_version, "1.2 & 3");
    assert_eq!(d.identity.firmware_version, "<4.5>");
    assert_eq!(d.identity.hardware_version, "B&C");
    assert_eq!(
        d.file_info.description,
        "A drive & <its> motor\non two lines"
    );
    let gain = d.dictionary.object(0x2000).unwrap();
    assert_eq!(gain.description.as_deref(), Some("Gain < & > factor"));
    // A label that is not the entry's name is its description where there is no other.
    assert_eq!(
        d.dictionary.object(0x2001).unwrap().description.as_deref(),
        Some("Offset & bias")
    );
    assert_eq!(d.dictionary.read_value(0x2000, 0).unwrap(), Value::Uint(7));
}

/// A CDATA section's line ends are read as text's are (CR LF as LF), in both readers.
#[test]
fn line_ends_in_cdata_read_as_in_text() {
    let xdd = XDD.replace("motor\non two lines", "motor\r\non two lines");
    let d = od::xdd::read(xdd.as_bytes(), "cdata.xdd").unwrap();
    assert_eq!(
        d.file_info.description,
        "A drive & <its> motor\non two lines"
    );
    let esi = ESI.replace("Object & comment", "Object\r\n& comment");
    let d = &od::esi::read_all(esi.as_bytes(), "cdata.xml").unwrap()[0];
    assert_eq!(
        d.dictionary.object(0x2000).unwrap().description.as_deref(),
        Some("Object\n& comment")
    );
}
