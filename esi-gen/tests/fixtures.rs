//! The generated descriptions committed under `fixtures/` are exactly what the generator makes from
//! `fixtures/src` and `fixtures/identity.toml`.

#[test]
fn committed_fixtures_are_byte_identical_to_a_regeneration() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures");
    let files = esi_gen::fixtures::generate(&root).expect("the sources load");
    assert_eq!(
        files.len(),
        11,
        "one ESI of both SMDs; EDS, XDD and doc of each; ESI, EDS, XDD and doc of the X67"
    );
    let stale = esi_gen::fixtures::stale(&files);
    assert!(
        stale.is_empty(),
        "run `esi-gen fixtures`; these differ: {stale:#?}"
    );
}

#[test]
fn generated_descriptions_carry_the_placeholder_identities() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures");
    let ids = esi_gen::IdentityFile::load(&root.join("identity.toml")).unwrap();
    let (_, devs) = od::load::load(&root.join("smd/SMD23K-B_SMD24K.esi.xml")).unwrap();
    for d in &devs {
        let e = ids
            .entry_for(d)
            .expect("every SMD device has an identity entry");
        assert_eq!(Some(d.identity.product_code), e.product_code);
        assert_eq!(Some(d.identity.vendor_id), e.vendor_id);
        assert_eq!(
            d.dictionary.read_value(0x1018, 2).unwrap(),
            od::Value::Uint(e.product_code.unwrap() as u64)
        );
    }
}
