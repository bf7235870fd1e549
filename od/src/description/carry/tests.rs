use super::*;

fn eds(original: &str, base: &str, edited: &str) -> String {
    rewrite_text(original, Format::Eds, base, edited).unwrap()
}

fn xml(original: &str, base: &str, edited: &str) -> String {
    rewrite_text(original, Format::Esi, base, edited).unwrap()
}

#[test]
fn an_unedited_file_comes_back_byte_for_byte() {
    let original = b"; made by hand\r\n[FileInfo]\r\nFileName=a.eds\r\nLastEDS=x\r\n";
    let base = "[FileInfo]\nFileName=a.eds\nDescription=\n";
    assert_eq!(
        rewrite(original, Format::Eds, base, base).unwrap(),
        original
    );
    let latin1 = b"<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?><R><N>\xB5</N></R>";
    assert_eq!(
        rewrite(latin1, Format::Esi, "<R/>", "<R/>").unwrap(),
        latin1
    );
}

#[test]
fn an_ini_value_changes_in_place_with_its_comment_and_unknown_keys_kept() {
    let original = "[FileInfo]\r\nFileName = a.eds ; the name\r\nLastEDS=x\r\n\r\n[1000]\r\nObjFlags=NV\r\nDefaultValue=0x191\r\n";
    let base = "[FileInfo]\nFileName=a.eds\n\n[1000]\nDefaultValue=0x191\n";
    let edited = "[FileInfo]\nFileName=b.eds\n\n[1000]\nDefaultValue=0x191\n";
    assert_eq!(
        eds(original, base, edited),
        "[FileInfo]\r\nFileName = b.eds ; the name\r\nLastEDS=x\r\n\r\n[1000]\r\nObjFlags=NV\r\nDefaultValue=0x191\r\n"
    );
}

#[test]
fn ini_keys_and_sections_come_and_go_where_the_edit_puts_them() {
    let original = "[A]\nk=1\n;note\nu=unknown\n\n[1018sub01]\nv=2\n[B]\nw=3\n";
    let base = "[A]\nk=1\n\n[1018sub1]\nv=2\n\n[B]\nw=3\n";
    let edited = "[A]\nk=1\nn=new\n\n[1018sub1]\nv=2\n\n[C]\nx=4\n\n[B]\n";
    assert_eq!(
        eds(original, base, edited),
        "[A]\nk=1\nn=new\n;note\nu=unknown\n\n[1018sub01]\nv=2\n[C]\nx=4\n\n[B]\n"
    );
}

#[test]
fn an_ini_section_the_edit_removes_goes_with_its_comments() {
    let original = "[A]\nk=1\n; about B\n[B]\n;in B\nw=3\n\n[C]\n";
    let base = "[A]\nk=1\n\n[B]\nw=3\n\n[C]\n";
    let edited = "[A]\nk=1\n\n[C]\n";
    assert_eq!(eds(original, base, edited), "[A]\nk=1\n; about B\n[C]\n");
}

#[test]
fn a_default_the_writer_adds_is_not_added_unless_edited() {
    let original = "[1000]\nDefaultValue=1\n";
    let base = "[1000]\nDefaultValue=1\nPDOMapping=0\n";
    let edited = "[1000]\nDefaultValue=2\nPDOMapping=0\n";
    assert_eq!(eds(original, base, edited), "[1000]\nDefaultValue=2\n");
    let edited = "[1000]\nDefaultValue=1\nPDOMapping=1\n";
    assert_eq!(
        eds(original, base, edited),
        "[1000]\nDefaultValue=1\nPDOMapping=1\n"
    );
}

#[test]
fn xml_attributes_change_in_place_come_and_go() {
    let original = "<R>\n  <Type ProductCode='#x1' RevisionNo=\"#x2\" Vendor=\"v\" CheckRevisionNo=\"EQ\">T</Type>\n</R>";
    let base = "<R>\n\t<Type ProductCode=\"#x1\" RevisionNo=\"#x2\" Vendor=\"v\">T</Type>\n</R>";
    let edited = "<R>\n\t<Type ProductCode=\"#x'9\" RevisionNo=\"#x2\" Extra=\"e\">T</Type>\n</R>";
    assert_eq!(
        xml(original, base, edited),
        "<R>\n  <Type ProductCode='#x&apos;9' RevisionNo=\"#x2\" CheckRevisionNo=\"EQ\" Extra=\"e\">T</Type>\n</R>"
    );
}

#[test]
fn xml_text_changes_in_place_and_fills_an_empty_tag() {
    let original =
        "<R><Name LcId=\"1033\">A &amp; B</Name><Name LcId=\"1031\">C</Name><Group/></R>";
    let base =
        "<R><Name LcId=\"1033\">A &amp; B</Name><Name LcId=\"1031\">C</Name><Group></Group></R>";
    let edited = "<R><Name LcId=\"1033\">A</Name><Name LcId=\"1031\">C</Name><Group>G</Group></R>";
    assert_eq!(
        xml(original, base, edited),
        "<R><Name LcId=\"1033\">A</Name><Name LcId=\"1031\">C</Name><Group>G</Group></R>"
    );
}

#[test]
fn xml_elements_unknown_to_the_model_stay_and_edits_around_them_land() {
    let original = "<R>\n    <Object>\n        <Index>#x1000</Index>\n        <Flags><Category>m</Category></Flags>\n    </Object>\n    <!-- two -->\n    <Object>\n        <Index>#x2000</Index>\n    </Object>\n</R>\n";
    let base = "<R>\n  <Object>\n    <Index>#x1000</Index>\n  </Object>\n  <Object>\n    <Index>#x2000</Index>\n  </Object>\n</R>\n";
    let edited = "<R>\n  <Object>\n    <Index>#x1000</Index>\n  </Object>\n  <Object>\n    <Index>#x1800</Index>\n    <Name>new</Name>\n  </Object>\n</R>\n";
    assert_eq!(
        xml(original, base, edited),
        "<R>\n    <Object>\n        <Index>#x1000</Index>\n        <Flags><Category>m</Category></Flags>\n    </Object>\n    <Object>\n        <Index>#x1800</Index>\n        <Name>new</Name>\n    </Object>\n    <!-- two -->\n</R>\n"
    );
}

#[test]
fn an_element_goes_into_an_empty_tag_indented() {
    let original = "<R>\n\t<Sm a=\"1\"/>\n</R>";
    let base = "<R>\n  <Sm a=\"1\"></Sm>\n</R>";
    let edited = "<R>\n  <Sm a=\"1\">\n    <X>1</X>\n  </Sm>\n</R>";
    assert_eq!(
        xml(original, base, edited),
        "<R>\n\t<Sm a=\"1\">\n\t\t<X>1</X>\n\t</Sm>\n</R>"
    );
}

#[test]
fn an_edit_brings_characters_the_encoding_has_not_as_references() {
    let original = b"<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>\n<R><N>\xB5</N></R>";
    let out = rewrite(
        original,
        Format::Esi,
        "<R><N>\u{B5}</N></R>",
        "<R><N>\u{B5}\u{3A9}</N></R>",
    )
    .unwrap();
    assert_eq!(
        out,
        b"<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>\n<R><N>\xB5&#937;</N></R>"
    );
}

#[test]
fn unheld_parts_are_named_by_path() {
    let original =
        "<R Physics=\"YY\">\n<Object><Index>#x1000</Index><Flags/></Object>\n<!-- c -->\n</R>";
    let base = "<R><Object><Index>#x1000</Index></Object></R>";
    let got = unheld(original, Format::Esi, base).unwrap();
    let paths: Vec<&str> = got.iter().map(|u| u.path.as_str()).collect();
    assert_eq!(
        paths,
        ["R/@Physics", "R/Object[4096]/Flags", "R/#comment[1]"]
    );
    assert_eq!(got[0].text, "YY");
    let original = "[FileInfo]\nFileName=a\nLastEDS=b\n[Comments]\nLines=1\nLine1=x\n";
    let base = "[FileInfo]\nFileName=a\n";
    let got = unheld(original, Format::Eds, base).unwrap();
    let paths: Vec<&str> = got.iter().map(|u| u.path.as_str()).collect();
    assert_eq!(paths, ["[FileInfo] LastEDS", "[Comments]"]);
    assert_eq!(got[0].text, "b");
    assert_eq!(got[1].text, "[Comments]\nLines=1\nLine1=x");
}

#[test]
fn malformed_texts_are_errors() {
    assert!(rewrite_text("<R>", Format::Esi, "<R/>", "<R a=\"1\"/>").is_err());
}

#[test]
fn an_edited_part_takes_the_place_of_an_unheld_one_of_its_name() {
    // `NodeID=0xff` is no node-ID to the model, so its rendering has none; an edit that sets one
    // changes that line rather than adding a second.
    let original = "[DeviceComissioning]\nNodeID=0xff ; none\nBaudrate=500\n";
    let base = "[DeviceComissioning]\nBaudrate=500\n";
    let edited = "[DeviceComissioning]\nNodeID=5\nBaudrate=500\n";
    assert_eq!(
        eds(original, base, edited),
        "[DeviceComissioning]\nNodeID=5 ; none\nBaudrate=500\n"
    );
}

#[test]
fn esi_sub_items_pair_by_name_and_xdd_objects_whatever_their_prefix() {
    let original = "<I><SubItem><Name>A</Name><Info><D>1</D></Info></SubItem><SubItem><Name>C</Name><Info><D>3</D></Info></SubItem></I>";
    let base = "<I><SubItem><Name>A</Name><Info><D>1</D></Info></SubItem><SubItem><Name>B</Name><Info/></SubItem><SubItem><Name>C</Name><Info><D>3</D></Info></SubItem></I>";
    let edited = "<I><SubItem><Name>A</Name><Info><D>1</D></Info></SubItem><SubItem><Name>B</Name><Info><D>2</D></Info></SubItem><SubItem><Name>C</Name><Info><D>3</D></Info></SubItem></I>";
    assert_eq!(
        xml(original, base, edited),
        "<I><SubItem><Name>A</Name><Info><D>1</D></Info></SubItem>\n\t<SubItem><Name>B</Name><Info><D>2</D></Info></SubItem><SubItem><Name>C</Name><Info><D>3</D></Info></SubItem></I>"
    );
    let original = "<ObjectList><Object index=\"1018\" x=\"k\"><SubObject subIndex=\"02\" defaultValue=\"1\"/></Object></ObjectList>";
    let base = "<CANopenObjectList><CANopenObject index=\"1018\"><CANopenSubObject subIndex=\"02\" defaultValue=\"1\"/></CANopenObject></CANopenObjectList>";
    let edited = "<CANopenObjectList><CANopenObject index=\"1018\"><CANopenSubObject subIndex=\"02\" defaultValue=\"9\"/></CANopenObject></CANopenObjectList>";
    assert_eq!(
        rewrite_text(original, Format::Xdd, base, edited).unwrap(),
        "<ObjectList><Object index=\"1018\" x=\"k\"><SubObject subIndex=\"02\" defaultValue=\"9\"/></Object></ObjectList>"
    );
}

#[test]
fn families() {
    assert!(same_family(Format::Eds, Format::Dcf));
    assert!(same_family(Format::Dcf, Format::Eds));
    assert!(same_family(Format::Esi, Format::Esi));
    assert!(!same_family(Format::Esi, Format::Xdd));
    assert!(!same_family(Format::Eds, Format::Xdd));
    assert!(!same_family(Format::Dcf, Format::Esi));
}

fn read(text: &str, format: Format) -> Vec<DeviceDescription> {
    crate::load::read_bytes(text.as_bytes(), "test", format).unwrap()
}

const EDS: &str = "; notes\n[DeviceInfo]\nVendorNumber=0x1\nProductName=P\n\n[1017]\nParameterName=Producer heartbeat time\nDataType=0x0006\nAccessType=rw\nDefaultValue=0\nDenotation=beat\n";

#[test]
fn render_is_each_formats_writer() {
    let d = read(EDS, Format::Eds);
    assert_eq!(render(Format::Eds, &d), crate::eds::write_eds(&d[0]));
    assert_eq!(render(Format::Dcf, &d), crate::eds::write_dcf(&d[0]));
    assert_eq!(render(Format::Xdd, &d), crate::xdd::write(&d[0]));
    assert_eq!(render(Format::Esi, &d), crate::esi::write_all(&d));
    assert_eq!(render(Format::Eds, &[]), "");
}

#[test]
fn write_keeps_the_file_and_makes_the_edit() {
    let as_read = read(EDS, Format::Eds);
    let mut edited = as_read.clone();
    edited[0].identity.product_name = "Q".into();
    let w = write(EDS.as_bytes(), Format::Eds, &as_read, Format::Eds, &edited);
    assert_eq!(w.kept, Ok(()));
    assert_eq!(
        String::from_utf8(w.bytes).unwrap(),
        EDS.replace("ProductName=P", "ProductName=Q")
    );
    // Another family: the writer's rendering, and why.
    let w = write(EDS.as_bytes(), Format::Eds, &as_read, Format::Xdd, &edited);
    assert_eq!(w.kept, Err("EDS is no XDD".to_string()));
    assert_eq!(w.bytes, crate::xdd::write(&edited[0]).into_bytes());
}

#[test]
fn write_falls_back_when_the_kept_file_would_read_back_otherwise() {
    // An original the reader refuses (a section twice) against a model of its first section: kept,
    // the file would not read back, so the writer's rendering is written.
    let original = "[DeviceInfo]\nVendorNumber=0x1\nProductName=P\n[DeviceInfo]\nProductName=P\n";
    let as_read = read(
        "[DeviceInfo]\nVendorNumber=0x1\nProductName=P\n",
        Format::Eds,
    );
    let mut edited = as_read.clone();
    edited[0].identity.product_name = "Q".into();
    let w = write(
        original.as_bytes(),
        Format::Eds,
        &as_read,
        Format::Eds,
        &edited,
    );
    let why = w.kept.unwrap_err();
    assert!(
        why.starts_with(
            "it would not read back: written:4:2: section [DeviceInfo] appears a second time"
        ),
        "{why}"
    );
    assert_eq!(w.bytes, crate::eds::write_eds(&edited[0]).into_bytes());
}

#[test]
fn unheld_attributes_are_those_the_rendering_lacks_by_name() {
    let got = unheld("<R a=\"1\" Physics=\"YY\"/>", Format::Esi, "<R a=\"2\"/>").unwrap();
    assert_eq!(
        got,
        [Unheld {
            path: "R/@Physics".into(),
            text: "YY".into()
        }]
    );
}

#[test]
fn unheld_paths_name_repeats_and_prefixes() {
    let original = "<q:R xmlns:q=\"u\"><S/><S x=\"1\"/><Object><Index>#x10</Index></Object><Object><Index>#x10</Index><E/></Object></q:R>";
    let base =
        "<R><S/><S/><Object><Index>#x10</Index></Object><Object><Index>#x10</Index></Object></R>";
    let got = unheld(original, Format::Esi, base).unwrap();
    let paths: Vec<&str> = got.iter().map(|u| u.path.as_str()).collect();
    assert_eq!(paths, ["q:R/@q", "q:R/S[2]/@x", "q:R/Object[16][2]/E"]);
}

#[test]
fn unheld_in_a_file_decodes_it_and_renders_its_model() {
    let file = b"; n\n[DeviceInfo]\nVendorNumber=0x1\nCompactPDO=0x1\n";
    let devices = read(std::str::from_utf8(file).unwrap(), Format::Eds);
    let got = unheld_in_file(file, Format::Eds, &devices).unwrap();
    let paths: Vec<&str> = got.iter().map(|u| u.path.as_str()).collect();
    assert_eq!(paths, ["#comment[1]", "[DeviceInfo] CompactPDO"]);
}

#[test]
fn an_unchanged_attribute_keeps_its_spelling_beside_a_changed_one() {
    assert_eq!(
        xml(
            "<T ProductCode=\"#x1\" RevisionNo=\"#x2\">n</T>",
            "<T ProductCode=\"#x00000001\" RevisionNo=\"#x00000002\">n</T>",
            "<T ProductCode=\"#x00000001\" RevisionNo=\"#x00000003\">n</T>",
        ),
        "<T ProductCode=\"#x1\" RevisionNo=\"#x00000003\">n</T>"
    );
}

#[test]
fn a_text_edit_replaces_mixed_content_whole_and_keeps_the_start_tag() {
    assert_eq!(
        xml(
            "<R>\n  <Desc k=\"v\">x<b>y</b></Desc>\n</R>",
            "<R>\n\t<Desc>xy</Desc>\n</R>",
            "<R>\n\t<Desc>z</Desc>\n</R>",
        ),
        "<R>\n  <Desc k=\"v\">z</Desc>\n</R>"
    );
}

#[test]
fn an_empty_tag_stays_empty_when_nothing_goes_into_it() {
    assert_eq!(
        xml(
            "<R><Sm/></R>",
            "<R><Sm><X>1</X></Sm></R>",
            "<R><Sm a=\"2\"><X>1</X></Sm></R>",
        ),
        "<R><Sm a=\"2\"/></R>"
    );
}

#[test]
fn ini_additions_start_on_a_line_of_their_own() {
    assert_eq!(
        eds("[A]\nk=1", "[A]\nk=1\n", "[A]\nk=1\nn=2\n"),
        "[A]\nk=1\nn=2\n"
    );
    assert_eq!(eds("", "", "[A]\nk=1\n"), "[A]\nk=1\n");
}

#[test]
fn removals_take_their_line_when_they_stand_alone() {
    let base = "<R><A/><B/></R>";
    let edited = "<R><A/></R>";
    assert_eq!(xml("<R><A/> <B/></R>", base, edited), "<R><A/> </R>");
    assert_eq!(
        xml("<R>\n<A/>\n<B/>\n</R>", base, edited),
        "<R>\n<A/>\n</R>"
    );
    assert_eq!(
        xml("<R>\r\n\t<A/>\r\n\t<B/>\r\n</R>", base, edited),
        "<R>\r\n\t<A/>\r\n</R>"
    );
    assert_eq!(xml("<R><A/>x<B/></R>", base, edited), "<R><A/>x</R>");
    assert_eq!(
        eds("[A]\nk=1\n  n=2\n", "[A]\nk=1\nn=2\n", "[A]\nk=1\n"),
        "[A]\nk=1\n"
    );
    // The file's first part.
    assert_eq!(
        eds("[B]\nw=3\n[C]\n", "[B]\nw=3\n\n[C]\n", "[C]\n"),
        "[C]\n"
    );
}

#[test]
fn write_falls_back_when_the_kept_file_would_read_back_as_another_model() {
    // The model given is not the original's (its 0x1017 default is 0, the file's 5): kept, the
    // file would read back with 5, which the writer's rendering does not.
    let as_read = read(EDS, Format::Eds);
    let original = EDS.replace("DefaultValue=0", "DefaultValue=5");
    let mut edited = as_read.clone();
    edited[0].identity.product_name = "Q".into();
    let w = write(
        original.as_bytes(),
        Format::Eds,
        &as_read,
        Format::Eds,
        &edited,
    );
    let why = w.kept.unwrap_err();
    assert!(
        why.starts_with("it would read back otherwise: 0: "),
        "{why}"
    );
    assert!(why.contains("0x1017"), "{why}");
    assert_eq!(w.bytes, crate::eds::write_eds(&edited[0]).into_bytes());
}

#[test]
fn line_ends_follow_the_original() {
    assert_eq!(eol("a\nb", "\r\n"), "a\r\nb");
    assert_eq!(eol("a\r\nb", "\r\n"), "a\r\nb");
    assert_eq!(eol("ab", "\r\n"), "ab");
    assert_eq!(eol("a\r\nb", "\n"), "a\nb");
    assert_eq!(eol("a\nb", "\n"), "a\nb");
}

#[test]
fn utf16_files_stay_utf16_in_their_byte_order() {
    let utf16 = |text: &str, big_endian: bool| -> Vec<u8> {
        let mut out = if big_endian {
            vec![0xFE, 0xFF]
        } else {
            vec![0xFF, 0xFE]
        };
        for u in text.encode_utf16() {
            out.extend_from_slice(&if big_endian {
                u.to_be_bytes()
            } else {
                u.to_le_bytes()
            });
        }
        out
    };
    for big_endian in [false, true] {
        let original = utf16("<R><N>a</N><X/></R>", big_endian);
        let out = rewrite(
            &original,
            Format::Esi,
            "<R><N>a</N></R>",
            "<R><N>\u{3A9}</N></R>",
        )
        .unwrap();
        assert_eq!(
            out,
            utf16("<R><N>\u{3A9}</N><X/></R>", big_endian),
            "{big_endian}"
        );
    }
}
