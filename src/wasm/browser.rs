//! Where the solver meets the browser, through web-sys: the clock (`performance.now()` of the
//! page's window or of the worker) and the console. Nothing else in the crate knows the
//! browser; the core takes a clock as a closure.

use web_sys::js_sys::{Reflect, global};
use web_sys::wasm_bindgen::{JsCast, JsValue};
use web_sys::{Performance, Window, WorkerGlobalScope};

thread_local! {
    static PERFORMANCE: Performance = performance();
}

/// The global scope's `Performance`: the worker's or the window's, else (Node, where the wasm
/// tests run) the global `performance`.
fn performance() -> Performance {
    let scope = global();
    let found = if let Some(worker) = scope.dyn_ref::<WorkerGlobalScope>() {
        worker.performance()
    } else if let Some(window) = scope.dyn_ref::<Window>() {
        window.performance()
    } else {
        None
    };
    found.unwrap_or_else(|| {
        Reflect::get(&scope, &JsValue::from_str("performance"))
            .map(JsCast::unchecked_into)
            .expect("a global `performance` (browsers, Node ≥ 16)")
    })
}

/// Milliseconds of wall-clock time from the scope's time origin (`performance.now()`).
pub fn now_ms() -> f64 {
    PERFORMANCE.with(Performance::now)
}

/// A Rust panic shows in the console with its message, location and the JS stack
/// (`console.error`, through console_error_panic_hook). Installed once.
pub fn log_panics() {
    console_error_panic_hook::set_once();
}
