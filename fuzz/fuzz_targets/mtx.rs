//! Arbitrary bytes as the contents of a Matrix Market file: a matrix or a one-line error that
//! names the file, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Err(e) = wedged_cli::input::mtx::parse_bytes(data, "fuzz.mtx") {
        let message = e.to_string();
        assert!(message.starts_with("fuzz.mtx"), "{message}");
        assert!(!message.contains('\n'), "not one line: {message}");
    }
});
