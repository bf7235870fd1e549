//! CiA 311 XDD reader on arbitrary bytes: it must answer (a description or an error), never panic; what it
//! reads must be writable.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Ok(desc) = od::xdd::read(data, "fuzz") {
        let text = od::xdd::write(&desc);
        let _ = od::xdd::read(text.as_bytes(), "fuzz-rewritten");
    }
});
