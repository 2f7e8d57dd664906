//! One convolution layer's training cost (forward + backward on the autodiff device) with Burn's
//! differentiable `Conv1d::forward` against [`conv1d_gemm`] (the convolution as one matrix
//! product, differentiated through Burn's autodiff as plain tensor ops), interleaved in one
//! process so both see the same machine. Shapes: the stylizer's at the shipped and the paper's
//! width (batch 16 × 160 frames; the generator and encoders see 48–64 rows at 40 or 20 latent
//! frames).
//!
//! ```text
//! cargo run --release --example conv_train_bench [-- --rounds 5]
//! ```

#[cfg(not(feature = "model"))]
fn main() {
    eprintln!("conv_train_bench needs `--features model`");
}

#[cfg(feature = "model")]
fn main() {
    bench::main();
}

#[cfg(feature = "model")]
mod bench {
    use burn::prelude::*;
    use motion_stylizer::model::NoiseRng;
    use motion_stylizer::model::conv::conv1d_gemm;
    use motion_stylizer::model::layers::xavier_conv1d;
    use std::time::Instant;

    /// (rows, channels in, channels out, frames, kernel, stride).
    const SHAPES: [(usize, usize, usize, usize, usize, usize); 5] = [
        (48, 256, 384, 40, 3, 1),  // generator block 1, width 0.5
        (48, 512, 384, 80, 3, 1),  // generator block 3 (after ×2), width 0.5
        (64, 256, 384, 40, 3, 2),  // style encoder down 1, width 0.5
        (48, 512, 768, 40, 3, 1),  // generator block 1, width 1
        (48, 1024, 768, 80, 3, 1), // generator block 3, width 1
    ];

    fn time(rounds: usize, mut f: impl FnMut()) -> f64 {
        f();
        let t = Instant::now();
        for _ in 0..rounds {
            f();
        }
        t.elapsed().as_secs_f64() / rounds as f64
    }

    pub fn main() {
        let args: Vec<String> = std::env::args().collect();
        let rounds = args
            .iter()
            .position(|a| a == "--rounds")
            .and_then(|i| args.get(i + 1))
            .and_then(|v| v.parse().ok())
            .unwrap_or(5usize);
        let device = Device::flex().autodiff();
        let mut rng = NoiseRng::new(3);
        println!("forward + backward of one conv layer, ms (median of {rounds} interleaved rounds)");
        println!(
            "{:>5} {:>5} {:>5} {:>4} {:>2} {:>2} {:>10} {:>10} {:>7}",
            "rows", "c_in", "c_out", "T", "k", "s", "burn", "gemm", "ratio"
        );
        for (b, c_in, c_out, t, k, s) in SHAPES {
            let conv = xavier_conv1d(c_in, c_out, k, s, k / 2, true, &device);
            let x: Tensor<3> = rng.normal_tensor(b, c_in * t, &device).reshape([b, c_in, t]);
            let step = |gemm: bool| {
                let x = x.clone().require_grad();
                let y = if gemm { conv1d_gemm(&conv, x.clone()) } else { conv.forward(x.clone()) };
                let grads = (y.clone() * y).mean().backward();
                let _ = x.grad(&grads).map(|g| g.into_data());
            };
            let (mut burn, mut gemm) = (Vec::new(), Vec::new());
            for _ in 0..rounds {
                burn.push(time(1, || step(false)));
                gemm.push(time(1, || step(true)));
            }
            let median = |v: &mut Vec<f64>| {
                v.sort_by(f64::total_cmp);
                v[v.len() / 2] * 1e3
            };
            let (burn, gemm) = (median(&mut burn), median(&mut gemm));
            println!("{b:>5} {c_in:>5} {c_out:>5} {t:>4} {k:>2} {s:>2} {burn:>10.2} {gemm:>10.2} {:>7.2}", gemm / burn);
        }
    }
}
