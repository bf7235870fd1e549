//! Positions in files whose lines are long (a description written on one line): a column counts the
//! characters from the line's start, those of more than one byte as one, however far into the line.

use od::report::Reading;

/// An ESI of one device on one line, its vendor named by 400 characters of two and three bytes; a
/// revision number with its x doubled (a warning at the attribute) and object 0x6041 after the name.
fn esi_on_one_line() -> String {
    let vendor = "€µ".repeat(200);
    format!(
        "<?xml version=\"1.0\"?><EtherCATInfo><Vendor><Id>1</Id><Name>{vendor}</Name></Vendor>\
         <Descriptions><Groups/><Devices><Device><Type ProductCode=\"1\" RevisionNo=\"#xx2\">T</Type>\
         <Name>N</Name><Profile><Dictionary><DataTypes/><Objects><Object><Index>#x6041</Index>\
         <Name>Status</Name><Type>UINT</Type><BitSize>16</BitSize><Flags><Access>ro</Access></Flags>\
         </Object></Objects></Dictionary></Profile></Device></Devices></Descriptions></EtherCATInfo>"
    )
}

/// The warnings of a reading, each as `line:column: message`.
fn warnings(reading: &Reading) -> Vec<String> {
    reading
        .findings
        .iter()
        .map(|f| {
            let p = f.position.expect("a reader warning has a position");
            format!("{}:{}: {}", p.line, p.column, f.message)
        })
        .collect()
}

#[test]
fn an_esi_warning_far_into_one_line_is_at_its_character_column() {
    let text = esi_on_one_line();
    let attribute = text.find("RevisionNo").unwrap();
    // After 400 characters of 1000 bytes: byte 1137 is character 538.
    assert_eq!(attribute, 1137, "the attribute's byte offset");
    let reading = od::esi::read_file(text.as_bytes(), "one.xml").unwrap();
    assert_eq!(
        warnings(&reading),
        ["1:538: `#xx2` in the RevisionNo attribute has its hexadecimal prefix's x doubled; read as #x2"]
    );
    let object = reading.sources[0].object(0x6041).unwrap();
    assert_eq!((object.line, object.column), (1, 620));
}

#[test]
fn an_esi_with_its_line_breaks_has_the_same_warning_on_its_line() {
    let text = esi_on_one_line().replace("<Descriptions>", "\n<Descriptions>");
    let reading = od::esi::read_file(text.as_bytes(), "lines.xml").unwrap();
    assert_eq!(
        warnings(&reading),
        ["2:63: `#xx2` in the RevisionNo attribute has its hexadecimal prefix's x doubled; read as #x2"]
    );
}

#[test]
fn an_eds_error_far_into_a_line_is_at_its_character_column() {
    let text = format!("[FileInfo]\n[{}] x\n", "µ€".repeat(300));
    let e = od::eds::read_file(text.as_bytes(), "long.eds").unwrap_err();
    assert_eq!((e.position.line, e.position.column), (2, 604), "{e}");
    assert!(e.message.starts_with("unexpected text `x`"), "{e}");
}
