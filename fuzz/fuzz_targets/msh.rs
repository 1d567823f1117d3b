//! Arbitrary bytes as the contents of a Gmsh MSH file: a mesh or a one-line error that names
//! the file, never a panic.
//!
//! `msh::parse` runs the `mshio` crate inside `wedged_cli::contain_panic`, which turns a panic
//! of that third-party parser into an error. libFuzzer's panic hook aborts on every panic, even
//! a caught one, so by default this target reports those too (they mean a check missing before
//! `mshio`). With `WEDGED_FUZZ_ALLOW_CONTAINED=1` it lets them pass, as the program does.
#![no_main]

use std::sync::Once;

use libfuzzer_sys::fuzz_target;

static HOOK: Once = Once::new();

fuzz_target!(|data: &[u8]| {
    HOOK.call_once(|| {
        if std::env::var_os("WEDGED_FUZZ_ALLOW_CONTAINED").is_some_and(|v| v == "1") {
            let abort = std::panic::take_hook();
            std::panic::set_hook(Box::new(move |info| {
                if !wedged_cli::panic_is_contained() {
                    abort(info);
                }
            }));
        }
    });
    if let Err(e) = wedged_cli::input::msh::parse(data, "fuzz.msh") {
        let message = e.to_string();
        assert!(message.starts_with("fuzz.msh: "), "{message}");
        assert!(!message.contains('\n'), "not one line: {message}");
    }
});
