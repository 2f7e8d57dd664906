//! The compute device by name (`--device cpu|wgpu|cuda` of `train`, `stylize` and `eval`): one
//! function, [`open`], that every command uses.
//!
//! `cpu` is Burn's flex backend (always built; what every result of this project was computed
//! on). `wgpu` is Burn's wgpu runtime on the best adapter it finds (Vulkan natively; Mesa's
//! lavapipe on a machine without a GPU), built with the cargo feature `wgpu`. `cuda` is named but
//! never built: Burn's CUDA backend downloads a prebuilt LLVM while it builds (cubecl-cuda's
//! `tracel-llvm-bundler`), which this project's build machines cannot; wgpu reaches NVIDIA GPUs
//! through their Vulkan driver. A device this build lacks, or one that does not come up, is a
//! [`DeviceError`], not a panic.

use burn::prelude::*;

/// A device as the command line names it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum DeviceName {
    /// Burn's flex CPU backend.
    #[default]
    Cpu,
    /// Burn's wgpu runtime (feature `wgpu`).
    Wgpu,
    /// Burn's CUDA runtime: not built (see the module docs); an error saying so.
    Cuda,
}

impl DeviceName {
    pub const ALL: [DeviceName; 3] = [DeviceName::Cpu, DeviceName::Wgpu, DeviceName::Cuda];

    pub fn as_str(self) -> &'static str {
        match self {
            DeviceName::Cpu => "cpu",
            DeviceName::Wgpu => "wgpu",
            DeviceName::Cuda => "cuda",
        }
    }

    /// The cargo feature that builds the device in (`None`: always built, or never).
    pub fn feature(self) -> Option<&'static str> {
        match self {
            DeviceName::Wgpu => Some("wgpu"),
            DeviceName::Cpu | DeviceName::Cuda => None,
        }
    }

    /// Whether this build has the device's backend.
    pub fn compiled(self) -> bool {
        match self {
            DeviceName::Cpu => true,
            DeviceName::Wgpu => cfg!(all(feature = "wgpu", not(target_arch = "wasm32"))),
            DeviceName::Cuda => false,
        }
    }
}

impl core::fmt::Display for DeviceName {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl core::str::FromStr for DeviceName {
    type Err = DeviceError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        DeviceName::ALL
            .into_iter()
            .find(|d| d.as_str().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| DeviceError::Unknown(s.to_string()))
    }
}

/// Why a device cannot be used.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum DeviceError {
    #[error("unknown device {0:?}: the devices are cpu, wgpu and cuda")]
    Unknown(String),
    #[error(
        "this build has no {name} device: build with the cargo feature `{feature}` \
         (cargo build --release --features {feature})"
    )]
    NotCompiled { name: DeviceName, feature: &'static str },
    #[error("the {name} device did not come up: {message}")]
    Unavailable { name: DeviceName, message: String },
    #[error(
        "no build of this project has the cuda device (Burn's CUDA backend downloads a prebuilt LLVM \
         while it builds); on an NVIDIA GPU use --device wgpu (built with --features wgpu), which \
         runs on its Vulkan driver"
    )]
    CudaNotBuilt,
}

/// The device `name` (inference: no autodiff; training calls `.autodiff()` on it), brought up and
/// checked with a small computation read back. The wgpu runtime is initialised once per process;
/// later calls get a clone of it (or the same error).
pub fn open(name: DeviceName) -> Result<Device, DeviceError> {
    match name {
        DeviceName::Cpu => Ok(Device::flex()),
        DeviceName::Wgpu => wgpu(),
        DeviceName::Cuda => Err(DeviceError::CudaNotBuilt),
    }
}

/// The adapter's name as the runtime reports it (`None` on flex, or where the backend says none).
pub fn adapter_name(device: &Device) -> Option<String> {
    #[cfg(all(feature = "wgpu", not(target_arch = "wasm32")))]
    {
        return device.identity().map(|id| id.name);
    }
    #[allow(unreachable_code)]
    {
        let _ = device;
        None
    }
}

#[cfg(all(feature = "wgpu", not(target_arch = "wasm32")))]
fn wgpu() -> Result<Device, DeviceError> {
    static WGPU: std::sync::OnceLock<Result<Device, DeviceError>> = std::sync::OnceLock::new();
    WGPU.get_or_init(|| {
        let unavailable = |message: String| DeviceError::Unavailable { name: DeviceName::Wgpu, message };
        let device = guarded(|| Device::wgpu_options().init().map_err(|e| e.to_string()))
            .and_then(|r| r)
            .map_err(unavailable)?;
        probe(&device).map_err(unavailable)?;
        Ok(device)
    })
    .clone()
}

#[cfg(not(all(feature = "wgpu", not(target_arch = "wasm32"))))]
fn wgpu() -> Result<Device, DeviceError> {
    Err(DeviceError::NotCompiled { name: DeviceName::Wgpu, feature: "wgpu" })
}

/// A small matrix product on `device`, read back and checked, with the runtime's panics (no
/// driver, no adapter, a shader it cannot compile) turned into the error.
#[cfg(all(feature = "wgpu", not(target_arch = "wasm32")))]
fn probe(device: &Device) -> Result<(), String> {
    let values = guarded(|| {
        let a = Tensor::<2>::from_data(burn::tensor::TensorData::new(vec![1f32, 2., 3., 4.], [2, 2]), device);
        let b = a.clone().matmul(a).into_data();
        b.try_to_vec::<f32>().map_err(|e| format!("{e:?}"))
    })??;
    if values != [7.0, 10.0, 15.0, 22.0] {
        return Err(format!("a test product came back wrong: {values:?}"));
    }
    Ok(())
}

/// `f()`, a panic in it returned as its message (the runtimes panic where a driver is missing).
#[cfg(all(feature = "wgpu", not(target_arch = "wasm32")))]
fn guarded<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).map_err(|panic| {
        panic
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_else(|| "the runtime panicked".into())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_and_unknown_ones_are_errors() {
        for d in DeviceName::ALL {
            assert_eq!(d.as_str().parse::<DeviceName>(), Ok(d));
        }
        assert_eq!("WGPU".parse::<DeviceName>(), Ok(DeviceName::Wgpu));
        assert!(matches!("tpu".parse::<DeviceName>(), Err(DeviceError::Unknown(_))));
    }

    #[test]
    fn cpu_is_flex_and_missing_backends_name_their_feature() {
        assert_eq!(open(DeviceName::Cpu).unwrap(), Device::flex());
        if !DeviceName::Wgpu.compiled() {
            let e = open(DeviceName::Wgpu).unwrap_err();
            assert_eq!(e, DeviceError::NotCompiled { name: DeviceName::Wgpu, feature: "wgpu" });
            assert!(e.to_string().contains("--features wgpu"), "{e}");
        }
        let e = open(DeviceName::Cuda).unwrap_err();
        assert_eq!(e, DeviceError::CudaNotBuilt);
        assert!(e.to_string().contains("--device wgpu"), "{e}");
    }
}
