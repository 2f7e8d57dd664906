//! The browser's WebGPU device for [`super::Engine::create_webgpu`]: Burn's wgpu runtime on
//! `navigator.gpu`, built into the package's second wasm file (`engine-webgpu_bg.wasm`, the cargo
//! feature `wgpu` on wasm32; `make pkg`). Brought up once per instance, asynchronously (the web
//! has no blocking calls), and checked with a small product read back before any weights go to it.

use burn::prelude::Device;
use wasm_bindgen::JsValue;

use super::error::js_error;

fn unavailable(message: &str) -> JsValue {
    js_error("BACKEND_UNAVAILABLE", message)
}

#[cfg(feature = "wgpu")]
thread_local! {
    /// The device once it is up: Burn's wgpu runtime is initialised once per instance.
    static DEVICE: std::cell::RefCell<Option<Device>> = const { std::cell::RefCell::new(None) };
}

/// The WebGPU device, brought up on the first call. Errors (`BACKEND_UNAVAILABLE`): no adapter or
/// device, or a test product that does not come back right.
#[cfg(feature = "wgpu")]
pub(super) async fn device() -> Result<Device, JsValue> {
    if let Some(device) = DEVICE.with(|d| d.borrow().clone()) {
        return Ok(device);
    }
    let device =
        Device::wgpu_options().init_async().await.map_err(|e| unavailable(&format!("WebGPU did not come up: {e}")))?;
    probe(&device).await.map_err(|e| unavailable(&format!("WebGPU device does not compute: {e}")))?;
    DEVICE.with(|d| *d.borrow_mut() = Some(device.clone()));
    Ok(device)
}

/// The build without WebGPU (the default package): always `BACKEND_UNAVAILABLE`.
#[cfg(not(feature = "wgpu"))]
pub(super) async fn device() -> Result<Device, JsValue> {
    Err(unavailable("this build has no WebGPU backend (it is the package's engine-webgpu_bg.wasm)"))
}

/// A 2×2 product on `device`, read back asynchronously and checked.
#[cfg(feature = "wgpu")]
async fn probe(device: &Device) -> Result<(), String> {
    use burn::prelude::Tensor;
    use burn::tensor::TensorData;
    let a = Tensor::<2>::from_data(TensorData::new(vec![1f32, 2., 3., 4.], [2, 2]), device);
    let data = a.clone().matmul(a).into_data_async().await.map_err(|e| format!("{e:?}"))?;
    let values = data.try_into_vec_as::<f32>().map_err(|e| format!("{e:?}"))?;
    if values != [7.0, 10.0, 15.0, 22.0] {
        return Err(format!("a test product came back wrong: {values:?}"));
    }
    Ok(())
}
