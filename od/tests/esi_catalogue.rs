//! A module catalogue (ETG.2000 module description, root `EtherCATModule`) stays one: each of its
//! `Modules/Module`s is read as a description of its own that knows it is a catalogue's module, the ESI
//! writer writes such descriptions back as `EtherCATModule` with a `Module` each, element for element
//! as the file had them, and `od::diff` tells a catalogue from an `EtherCATInfo` of the same devices.

use od::device::{CatalogueModule, EsiRoot};
use od::diff::diff_devices;
use od::esi;
use od::DeviceDescription;
use quick_xml::events::Event;
use quick_xml::Reader;

/// An element: its name, its attributes' names and values, its text and its child elements.
#[derive(Debug, Default, PartialEq)]
struct El {
    name: String,
    attrs: Vec<(String, String)>,
    text: String,
    children: Vec<El>,
}

impl El {
    fn child(&self, name: &str) -> &El {
        self.children
            .iter()
            .find(|c| c.name == name)
            .unwrap_or_else(|| panic!("<{}> has no <{name}>", self.name))
    }

    fn names(&self) -> Vec<&str> {
        self.children.iter().map(|c| c.name.as_str()).collect()
    }

    /// The attribute names in sorted order, with their values.
    fn sorted_attrs(&self) -> Vec<(String, String)> {
        let mut a = self.attrs.clone();
        a.sort();
        a
    }

    /// Every element below, as its path of names from this one, in document order; the `SubIndex` 0
    /// of a gap (a PDO entry of index 0) is left out, as the model holds a gap as index 0, sub-index 0.
    fn paths(&self) -> Vec<String> {
        let zero = |t: &str| od::xml::parse_number(t) == Some(0);
        let gap = self.name == "Entry"
            && self
                .children
                .iter()
                .any(|c| c.name == "Index" && zero(&c.text));
        let mut out = Vec::new();
        for c in &self.children {
            if gap && c.name == "SubIndex" && zero(&c.text) {
                continue;
            }
            out.push(c.name.clone());
            out.extend(c.paths().into_iter().map(|p| format!("{}/{p}", c.name)));
        }
        out
    }
}

/// The root element of an XML text.
fn tree(text: &str) -> El {
    let mut reader = Reader::from_str(text);
    let mut stack: Vec<El> = vec![El::default()];
    let open = |e: &quick_xml::events::BytesStart| El {
        name: String::from_utf8_lossy(e.name().as_ref()).into_owned(),
        attrs: e
            .attributes()
            .map(|a| {
                let a = a.unwrap();
                (
                    String::from_utf8_lossy(a.key.as_ref()).into_owned(),
                    a.unescape_value().unwrap().into_owned(),
                )
            })
            .filter(|(k, _)| !k.starts_with("xmlns") && !k.starts_with("xsi:"))
            .collect(),
        ..El::default()
    };
    loop {
        match reader.read_event().unwrap() {
            Event::Start(e) => stack.push(open(&e)),
            Event::Empty(e) => {
                let el = open(&e);
                stack.last_mut().unwrap().children.push(el);
            }
            Event::End(_) => {
                let el = stack.pop().unwrap();
                stack.last_mut().unwrap().children.push(el);
            }
            Event::Text(t) => stack
                .last_mut()
                .unwrap()
                .text
                .push_str(t.xml10_content().unwrap().trim()),
            Event::Eof => break,
            _ => {}
        }
    }
    stack.pop().unwrap().children.pop().unwrap()
}

fn fixture() -> Vec<u8> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fixtures/module-catalogue.xml"
    );
    std::fs::read(path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn read(bytes: &[u8], name: &str) -> Vec<DeviceDescription> {
    esi::read_all(bytes, name).unwrap_or_else(|e| panic!("{e}"))
}

fn catalogue_module(d: &DeviceDescription) -> &CatalogueModule {
    match &d.ethercat.as_ref().expect("an ESI description").root {
        EsiRoot::EtherCatModule(m) => m,
        other => panic!(
            "{} is read as a device of an {}",
            d.identity.order_code,
            other.element()
        ),
    }
}

#[test]
fn each_module_of_a_catalogue_is_a_description_that_knows_its_file() {
    let ds = read(&fixture(), "module-catalogue.xml");
    assert_eq!(ds.len(), 2);
    assert_eq!(
        catalogue_module(&ds[0]),
        &CatalogueModule {
            ident: 0x0001_0001,
            class: "DIO".into(),
            pdo_group: Some(1),
            profile_no: Some(5001),
            add_info: Some(0),
            dc_op_mode_name: "Synchron".into(),
        }
    );
    assert_eq!(
        catalogue_module(&ds[1]),
        &CatalogueModule {
            ident: 0x0001_0002,
            class: "AI".into(),
            pdo_group: None,
            profile_no: Some(5001),
            add_info: None,
            dc_op_mode_name: String::new(),
        }
    );
    let d = &ds[0];
    assert_eq!(d.identity.vendor_id, 0xABC);
    assert_eq!(d.identity.order_code, "EX-2DIO");
    assert_eq!(d.file_info.file_version, "7");
    let ecat = d.ethercat.as_ref().unwrap();
    assert_eq!(ecat.rx_pdos[0].entries.len(), 3);
    assert!(ecat.rx_pdos[0].index_depend.slot);
    assert_eq!(
        ecat.mailbox.as_ref().unwrap().init_cmds[0].comment,
        "Filter on"
    );
    assert!(
        ecat.mailbox.as_ref().unwrap().init_cmds[0]
            .index_depend
            .slot
    );
    assert!(ecat.sync_managers.is_empty() && ecat.modules.is_empty());
}

/// The written catalogue against the file it was read from: the root and its children, each `Module`'s
/// elements in order, the `Type` attributes and text, and every element of the PDOs and the mailbox.
/// A module's `Profile` always holds a `Dictionary` (the second module's is made from its PDO).
fn compare_catalogue(input: &El, written: &El, what: &str) {
    assert_eq!(written.name, "EtherCATModule", "{what}");
    assert_eq!(
        written.names(),
        input.names(),
        "{what}: the root's children"
    );
    let (a, b) = (input.child("Modules"), written.child("Modules"));
    assert_eq!(a.children.len(), b.children.len(), "{what}: modules");
    for (m, w) in a.children.iter().zip(&b.children) {
        let ty = &m.child("Type").text;
        assert_eq!(w.names(), m.names(), "{what}: the elements of module {ty}");
        assert_eq!(
            w.child("Type").sorted_attrs(),
            m.child("Type").sorted_attrs(),
            "{what}: <Type> of {ty}"
        );
        assert_eq!(&w.child("Type").text, ty, "{what}");
        assert_eq!(w.child("Name").text, m.child("Name").text, "{what}: {ty}");
        for part in ["RxPdo", "TxPdo", "Mailbox"] {
            let (x, y): (Vec<&El>, Vec<&El>) = (
                m.children.iter().filter(|c| c.name == part).collect(),
                w.children.iter().filter(|c| c.name == part).collect(),
            );
            for (x, y) in x.iter().zip(&y) {
                assert_eq!(y.paths(), x.paths(), "{what}: <{part}> of {ty}");
            }
        }
        let profile: Vec<&str> = m.child("Profile").names();
        let mut expected: Vec<&str> = profile.clone();
        if !expected.contains(&"Dictionary") {
            expected.push("Dictionary");
        }
        assert_eq!(w.child("Profile").names(), expected, "{what}: {ty}");
    }
}

#[test]
fn a_catalogue_is_written_back_as_a_catalogue_and_reads_back_the_same() {
    let bytes = fixture();
    let ds = read(&bytes, "module-catalogue.xml");
    let written = esi::write_all(&ds);
    assert!(
        written.contains("<EtherCATModule ") && !written.contains("EtherCATInfo"),
        "{written}"
    );
    assert!(!written.contains("<Device>") && !written.contains("<Descriptions>"));
    compare_catalogue(
        &tree(std::str::from_utf8(&bytes).unwrap()),
        &tree(&written),
        "fixture",
    );
    let back = read(written.as_bytes(), "written.xml");
    assert_eq!(back, ds);
    for (a, b) in ds.iter().zip(&back) {
        assert_eq!(diff_devices(a, b), vec![]);
    }
    // One module alone is a catalogue of one.
    let one = esi::write(&ds[1]);
    assert_eq!(tree(&one).child("Modules").children.len(), 1);
    assert_eq!(read(one.as_bytes(), "one.xml"), vec![ds[1].clone()]);
}

#[test]
fn a_catalogue_differs_from_an_ethercat_info_of_the_same_devices() {
    let ds = read(&fixture(), "module-catalogue.xml");
    let mut devices = ds.clone();
    for d in &mut devices {
        d.ethercat.as_mut().unwrap().root = EsiRoot::EtherCatInfo;
    }
    let info = esi::write_all(&devices);
    assert_eq!(tree(&info).name, "EtherCATInfo");
    let back = read(info.as_bytes(), "info.xml");
    assert_eq!(back.len(), 2);
    for (a, b) in ds.iter().zip(&back) {
        assert_ne!(a, b);
        let diffs: Vec<String> = diff_devices(a, b).iter().map(|d| d.to_string()).collect();
        assert_eq!(
            diffs,
            ["~ root element: EtherCATModule -> EtherCATInfo"],
            "{}",
            a.identity.order_code
        );
    }
    // A catalogue's module among devices is written in the EtherCATInfo, as a device.
    let mixed = esi::write_all(&[devices[0].clone(), ds[1].clone()]);
    assert_eq!(tree(&mixed).name, "EtherCATInfo");
    assert_eq!(read(mixed.as_bytes(), "mixed.xml").len(), 2);
}

/// The catalogue of the corpus (`weidmueller-UR20_IO.xml`, 82 modules): written back as one, element
/// for element, and read back the same.
#[test]
fn the_corpus_catalogue_stays_one() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../shared/corpus/esi/weidmueller-UR20_IO.xml"
    );
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let ds = read(&bytes, "weidmueller-UR20_IO.xml");
    assert_eq!(ds.len(), 82);
    let m = catalogue_module(&ds[0]);
    assert_eq!((m.ident, m.class.as_str()), (0x0009_1F84, "Di"));
    assert_eq!(
        (m.pdo_group, m.profile_no, m.add_info),
        (Some(1), Some(5001), Some(0))
    );
    let written = esi::write_all(&ds);
    compare_catalogue(
        &tree(std::str::from_utf8(&bytes).unwrap()),
        &tree(&written),
        "weidmueller-UR20_IO.xml",
    );
    let back = read(written.as_bytes(), "written.xml");
    assert_eq!(format!("{back:?}"), format!("{ds:?}"));
}
