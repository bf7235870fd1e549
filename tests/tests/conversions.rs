//! Each generated fixture read back against its source: the only differences are the ones its format
//! cannot carry, each named here.

use integration_tests::{fixture, load_all};
use od::device::DeviceDescription;
use od::diff::{diff, Change, Difference};

fn sources() -> (Vec<DeviceDescription>, DeviceDescription) {
    let ids = esi_gen::IdentityFile::load(&fixture("identity.toml")).unwrap();
    let mut smd = load_all(&fixture("src/smd.esi.xml"));
    for d in &mut smd {
        ids.apply(d);
    }
    let mut x67 = load_all(&fixture("src/x67sm2436.xdd")).remove(0);
    ids.apply(&mut x67);
    (smd, x67)
}

/// Every difference between `a` and `b` that `allowed` does not excuse.
fn unexplained(
    a: &DeviceDescription,
    b: &DeviceDescription,
    allowed: impl Fn(&Difference) -> bool,
) -> Vec<String> {
    diff(&a.dictionary, &b.dictionary)
        .iter()
        .filter(|d| !allowed(d))
        .map(|d| d.to_string())
        .collect()
}

fn changed(d: &Difference) -> Option<(u16, &'static str, &str, &str)> {
    match &d.change {
        Change::Changed { field, a, b } => Some((d.index()?, *field, a.as_str(), b.as_str())),
        _ => None,
    }
}

#[test]
fn xdd_carries_the_whole_dictionary_of_both_devices() {
    let (smd, x67) = sources();
    for dev in &smd {
        let name = &dev.identity.order_code;
        let back = load_all(&fixture(&format!("smd/{name}.xdd"))).remove(0);
        assert_eq!(
            unexplained(dev, &back, |_| false),
            Vec::<String>::new(),
            "{name}"
        );
    }
    let back = load_all(&fixture("x67/X67SM2436.xdd")).remove(0);
    assert_eq!(unexplained(&x67, &back, |_| false), Vec::<String>::new());
}

/// EDS has no string capacity, and tells the PDO direction by the access type, so an ESI output object
/// (`ro`, RPDO) comes back `rww`; nor has it the structure type names (`DT1018`) or the descriptions of
/// objects and entries.
#[test]
fn eds_loses_string_capacities_and_spells_outputs_rww() {
    let (smd, x67) = sources();
    for dev in &smd {
        let name = &dev.identity.order_code;
        let back = load_all(&fixture(&format!("smd/{name}.eds"))).remove(0);
        let unsaid = |d: &Difference| {
            matches!(
                changed(d),
                Some((_, "type name" | "description", _, "none"))
            )
        };
        let left = unexplained(dev, &back, |d| {
            unsaid(d)
                || matches!(
                    changed(d),
                    Some((0x1008..=0x100A, "size", _, "unbounded"))
                        | Some((0x7000, "access", "ro", "rww"))
                )
        });
        assert_eq!(left, Vec::<String>::new(), "{name}");
        assert_eq!(
            diff(&dev.dictionary, &back.dictionary)
                .iter()
                .filter(|d| !unsaid(d))
                .count(),
            3 + 8,
            "{name}"
        );
    }
    let back = load_all(&fixture("x67/X67SM2436.eds")).remove(0);
    assert_eq!(unexplained(&x67, &back, |_| false), Vec::<String>::new());
}

/// ESI has no `const`, `rww` or `$NODEID`: those come back as `ro`, `rw` and the node-0 value, an
/// unbounded string gets the length of its default, and each ARRAY and RECORD gets a structure type
/// name (`DT1018`).
#[test]
fn esi_of_the_canopen_module_loses_only_what_esi_cannot_say() {
    let (_, x67) = sources();
    let back = load_all(&fixture("x67/X67SM2436.esi.xml")).remove(0);
    let left = unexplained(&x67, &back, |d| match changed(d) {
        Some((0x1008, "access", "const", "ro")) => true,
        Some((0x1008, "size", "unbounded", _)) => true,
        Some((_, "default", a, b)) => a.strip_prefix("$NODEID+") == Some(b),
        Some((0x2000..=0x2FFF, "access", "rww", "rw")) => true,
        Some((index, "type name", "none", b)) => b == format!("DT{index:04X}"),
        _ => false,
    });
    assert_eq!(left, Vec::<String>::new());
}

#[test]
fn the_esi_of_both_smds_reads_back_equal() {
    let (smd, _) = sources();
    let back = load_all(&fixture("smd/SMD23K-B_SMD24K.esi.xml"));
    assert_eq!(back.len(), 2);
    for (a, b) in smd.iter().zip(&back) {
        assert_eq!(unexplained(a, b, |_| false), Vec::<String>::new());
        assert_eq!(a.ethercat, b.ethercat);
        assert_eq!(a.identity, b.identity);
    }
}
