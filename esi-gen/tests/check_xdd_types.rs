//! `esi-gen check` on XDDs whose `dataTypeList` no device can have: a type made of itself, through
//! another, and an array of 2^32−1 elements. Each is one error at the file, line and column of what
//! makes it so, and exit 1; the reader neither hangs nor makes anything per declared element.

use std::path::PathBuf;
use std::process::Command;

/// A fresh folder for one test.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("esi-gen-xdd-types-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// An XDD with `types` in its `dataTypeList` (from line 7) and a device type object.
fn xdd(types: &str) -> String {
    format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<ISO15745ProfileContainer xmlns="http://www.canopen.org/xml/1.0" xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">
  <ISO15745Profile>
    <ProfileBody xsi:type="ProfileBody_Device_CANopen" fileName="t.xdd">
      <ApplicationProcess>
        <dataTypeList>
{types}
        </dataTypeList>
      </ApplicationProcess>
    </ProfileBody>
  </ISO15745Profile>
  <ISO15745Profile>
    <ProfileBody xsi:type="ProfileBody_CommunicationNetwork_CANopen" fileName="t.xdd">
      <ApplicationLayers>
        <CANopenObjectList>
          <CANopenObject index="1000" name="Device type" objectType="7" dataType="0007" accessType="ro" defaultValue="0"/>
        </CANopenObjectList>
      </ApplicationLayers>
    </ProfileBody>
  </ISO15745Profile>
</ISO15745ProfileContainer>
"#
    )
}

/// `esi-gen check FILE`: its exit code and its output with the time taken replaced by `T`.
fn check(path: &str) -> (Option<i32>, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_esi-gen"))
        .args(["check", path])
        .output()
        .expect("runs");
    let text = String::from_utf8_lossy(&o.stdout);
    let (head, rest) = text.split_once(", read and checked in ").expect("summary");
    let (_, rest) = rest.split_once(" ms\n").expect("time");
    (
        o.status.code(),
        format!("{head}, read and checked in T ms\n{rest}"),
    )
}

/// A struct (line 7) whose second member (line 9) is an array of the struct: the circle is named
/// at the member's `uniqueIDRef` value, line 9, column 90.
#[test]
fn a_struct_made_of_an_array_of_itself_is_an_error() {
    let dir = folder("circle");
    let file = dir.join("circle.xdd");
    std::fs::write(
        &file,
        xdd(r#"          <struct uniqueID="UID_REC" name="Pair">
            <varDeclaration uniqueID="UID_REC_1" name="first"><UINT/></varDeclaration>
            <varDeclaration uniqueID="UID_REC_2" name="rest"><dataTypeIDRef uniqueIDRef="UID_ARR"/></varDeclaration>
          </struct>
          <array uniqueID="UID_ARR" name="Pairs">
            <subrange lowerLimit="1" upperLimit="4"/>
            <dataTypeIDRef uniqueIDRef="UID_REC"/>
          </array>"#),
    )
    .unwrap();
    let p = file.display().to_string();
    assert_eq!(
        check(&p),
        (
            Some(1),
            format!(
                "{p}: XDD, 0 device(s), read and checked in T ms\n\
                 \n\
                 findings: 1 error(s), 0 warning(s)\n\
                 \x20 {p}:9:90: error: data type `UID_REC` (Pair) refers to itself through `UID_ARR`\n"
            )
        )
    );
}

/// An array of sub-indices 1 to 4294967295 (2^32−1 elements) is an error at its upperLimit (line
/// 8, column 50), found at once; an array of 1 to 254, the most an ARRAY holds, passes.
#[test]
fn an_array_of_more_elements_than_sub_indices_is_an_error() {
    let dir = folder("big");
    let big = dir.join("big.xdd");
    let array = |upper: &str| {
        xdd(&format!(
            r#"          <array uniqueID="UID_BIG" name="Samples">
            <subrange lowerLimit="1" upperLimit="{upper}"/>
            <UINT/>
          </array>"#
        ))
    };
    std::fs::write(&big, array("4294967295")).unwrap();
    let p = big.display().to_string();
    let started = std::time::Instant::now();
    let outcome = check(&p);
    assert!(
        started.elapsed() < std::time::Duration::from_secs(30),
        "{:?}",
        started.elapsed()
    );
    assert_eq!(
        outcome,
        (
            Some(1),
            format!(
                "{p}: XDD, 0 device(s), read and checked in T ms\n\
                 \n\
                 findings: 1 error(s), 0 warning(s)\n\
                 \x20 {p}:8:50: error: array `UID_BIG` (Samples) has elements 1 to 4294967295 \
                 (subrange): no ARRAY holds them, CiA 301 sub-indices go to 0xFE\n"
            )
        )
    );
    let most = dir.join("most.xdd");
    std::fs::write(&most, array("254")).unwrap();
    let (code, text) = check(&most.display().to_string());
    assert_eq!(code, Some(0), "{text}");
    assert!(
        text.contains("\nfindings: 0 error(s), 1 warning(s)\n"),
        "{text}"
    );
}
