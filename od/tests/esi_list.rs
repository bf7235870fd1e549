//! An `EtherCATInfoList` (ETG.2000's list of `EtherCATInfo`s; IgH's `ethercat xml` writes the slaves of
//! a bus as one) stays one: each `EtherCATInfo` in it is read as a file of its own, its vendor and
//! modules its devices' alone, each device knowing its place in the list; the ESI writer writes such
//! descriptions back as the list, one `EtherCATInfo` per place; `od::diff` tells a list from an
//! `EtherCATInfo` of the same devices. A list that is not closed, or holds anything but
//! `EtherCATInfo`s, is refused with the place.

use od::device::EsiRoot;
use od::diff::diff_devices;
use od::esi;

/// A device element of type `name`, product code `code`, with one TxPDO entry.
fn device(name: &str, code: u32) -> String {
    format!(
        "<Device><Type ProductCode=\"#x{code:08x}\" RevisionNo=\"#x00010000\">{name}</Type>\
         <Name><![CDATA[{name} & co]]></Name>\
         <Sm Enable=\"1\" StartAddress=\"#x1180\" ControlByte=\"#x20\" DefaultSize=\"2\" />\
         <TxPdo Sm=\"0\" Fixed=\"1\" Mandatory=\"1\"><Index>#x1a00</Index><Name>In</Name>\
         <Entry><Index>#x6000</Index><SubIndex>1</SubIndex><BitLen>16</BitLen><Name>Value</Name>\
         <DataType>UINT16</DataType></Entry></TxPdo></Device>"
    )
}

/// The list the tests read: vendor 2 with two devices and a module; vendor 154 (decimal, no name)
/// with one device.
fn list() -> String {
    format!(
        "<?xml version=\"1.0\" ?>\n<EtherCATInfoList>\n\
         <EtherCATInfo><!-- Slave 0 --><Vendor FileVersion=\"7\"><Id>2</Id><Name>Beckhoff</Name></Vendor>\
         <Descriptions><Devices>{}{}</Devices>\
         <Modules><Module><Type ModuleIdent=\"#x10\">M1</Type><Name>M1</Name></Module></Modules>\
         </Descriptions></EtherCATInfo>\n\
         <EtherCATInfo><Vendor><Id>154</Id></Vendor><Descriptions><Devices>{}</Devices></Descriptions>\
         </EtherCATInfo>\n</EtherCATInfoList>\n",
        device("EL3102", 0x0c1e3052),
        device("EL3104", 0x0c203052),
        device("Gold", 0x30924)
    )
}

fn read(text: &str) -> Vec<od::DeviceDescription> {
    esi::read_all(text.as_bytes(), "list.xml").expect("reads")
}

#[test]
fn each_info_of_a_list_gives_its_devices_their_vendor_and_place() {
    let ds = read(&list());
    let seen: Vec<(&str, u32, &str, &str, EsiRoot, usize)> = ds
        .iter()
        .map(|d| {
            let e = d.ethercat.as_ref().unwrap();
            (
                d.identity.order_code.as_str(),
                d.identity.vendor_id,
                d.identity.vendor_name.as_str(),
                d.file_info.file_version.as_str(),
                e.root.clone(),
                e.modules.len(),
            )
        })
        .collect();
    assert_eq!(
        seen,
        [
            (
                "EL3102",
                2,
                "Beckhoff",
                "7",
                EsiRoot::EtherCatInfoList(0),
                1
            ),
            (
                "EL3104",
                2,
                "Beckhoff",
                "7",
                EsiRoot::EtherCatInfoList(0),
                1
            ),
            ("Gold", 154, "", "", EsiRoot::EtherCatInfoList(1), 0),
        ]
    );
    assert_eq!(ds[2].identity.product_name, "Gold & co");
    assert_eq!(EsiRoot::EtherCatInfoList(1).element(), "EtherCATInfoList");
}

#[test]
fn a_list_is_written_back_as_a_list_and_reads_back_the_same() {
    let ds = read(&list());
    let written = esi::write_all(&ds);
    let roots: Vec<&str> = written
        .lines()
        .map(str::trim)
        .filter(|l| l.starts_with("<EtherCATInfo") || l.starts_with("</EtherCATInfo"))
        .map(|l| l.split([' ', '>']).next().unwrap())
        .collect();
    assert_eq!(
        roots,
        [
            "<EtherCATInfoList",
            "<EtherCATInfo",
            "</EtherCATInfo",
            "<EtherCATInfo",
            "</EtherCATInfo",
            "</EtherCATInfoList"
        ],
        "{written}"
    );
    assert_eq!(read(&written), ds);
    // No descriptions at all make an EtherCATInfo without devices.
    let none = esi::write_all(&[]);
    assert!(none.contains("\n<EtherCATInfo "), "{none}");
    assert!(!none.contains("<Device>"), "{none}");
}

#[test]
fn a_list_differs_from_an_ethercat_info_of_the_same_devices() {
    let ds = read(&list());
    let mut devices = ds.clone();
    for d in &mut devices {
        d.ethercat.as_mut().unwrap().root = EsiRoot::EtherCatInfo;
    }
    let info = esi::write_all(&devices[..2]);
    assert!(info.contains("\n<EtherCATInfo "), "{info}");
    assert!(!info.contains("EtherCATInfoList"), "{info}");
    let back = read(&info);
    let diffs: Vec<String> = diff_devices(&ds[0], &back[0])
        .iter()
        .map(|d| d.to_string())
        .collect();
    assert_eq!(diffs, ["~ root element: EtherCATInfoList -> EtherCATInfo"]);
}

#[test]
fn a_list_not_closed_or_holding_other_elements_is_refused_with_the_place() {
    let refused = |text: &str| {
        esi::read_all(text.as_bytes(), "l.xml")
            .unwrap_err()
            .to_string()
    };
    let open = "<EtherCATInfoList>\n<EtherCATInfo><Vendor><Id>2</Id></Vendor></EtherCATInfo>\n";
    assert_eq!(
        refused(open),
        "l.xml:3:1: unexpected end of file: <EtherCATInfoList> is not closed"
    );
    assert_eq!(
        refused("<EtherCATInfoList>\n  <Device/>\n</EtherCATInfoList>"),
        "l.xml:2:3: expected an <EtherCATInfo> in the <EtherCATInfoList>, found <Device>"
    );
    assert_eq!(
        refused("<EtherCATInfoList>\n</EtherCATInfoList>\n<EtherCATInfo/>"),
        "l.xml:3:1: a second root element <EtherCATInfo>: a file has one"
    );
    assert_eq!(
        refused("<EtherCATInfo/>\n<EtherCATInfo/>"),
        "l.xml:2:1: a second root element <EtherCATInfo>: a file has one"
    );
    assert_eq!(
        refused("<Other/>"),
        "l.xml:1:1: expected an <EtherCATInfo> root element, found <Other>"
    );
    assert_eq!(
        refused("<EtherCATInfo/>\n<EtherCATInfoList/>"),
        "l.xml:2:1: a second root element <EtherCATInfoList>: a file has one"
    );
    assert_eq!(
        refused("<EtherCATInfoList/>\n<EtherCATInfoList/>"),
        "l.xml:2:1: a second root element <EtherCATInfoList>: a file has one"
    );
    // An empty list has no devices.
    assert_eq!(read("<EtherCATInfoList></EtherCATInfoList>"), []);
}
