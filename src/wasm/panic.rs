//! The backstop for bugs: a panic hook that records the panic's message. On
//! `wasm32-unknown-unknown` a panic aborts, which traps the instance (JS sees a
//! `WebAssembly.RuntimeError` and nothing else); the JS wrapper then reads the message with
//! [`take_panic`], reports it as an `INTERNAL` error and replaces the instance with a fresh one.

use std::cell::RefCell;
use std::sync::Once;

use wasm_bindgen::prelude::*;

thread_local! {
    static LAST: RefCell<Option<String>> = const { RefCell::new(None) };
}

/// Installs the hook, once per instance (the facade's constructors call it). The hook that was
/// there before (wasm-bindgen-test's, in the tests) still runs after it.
pub(super) fn install() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            let message = info.to_string();
            // Inside a panic nothing may panic again: a busy or destroyed cell drops the message.
            let _ = LAST.try_with(|last| last.try_borrow_mut().map(|mut last| *last = Some(message)));
            previous(info);
        }));
    });
}

/// The message of the panic that trapped this instance, if one did ("panicked at FILE:LINE:COL:"
/// and the panic's text); taken, so a second call gives `undefined`.
#[wasm_bindgen(js_name = takePanic)]
pub fn take_panic() -> Option<String> {
    LAST.try_with(|last| last.try_borrow_mut().ok().and_then(|mut last| last.take())).ok().flatten()
}
