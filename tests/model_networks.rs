//! Shapes, AdaIN, length rules, losses, determinism and f16 weights of the stylization networks.
//! Small widths (`scaled(0.125)`) and short clips (T = 32) keep this fast in debug builds.
#![cfg(feature = "model")]

use burn::prelude::*;
use motion_stylizer::model::classifier::StyleClassifier;
use motion_stylizer::model::conv::{
    SHIFTED_MIN_BATCH, conv1d_gemm, conv1d_gemm_cbt, conv3_shifted_cbt, conv3_shifted_on_cpu, fold_upsampling_taps,
    interleave_parities, interleave_parities_by_tensor_ops, split_taps, upsample2_conv1d_gemm_cbt,
    upsample2_conv1d_on_cpu, winograd_pays,
};
use motion_stylizer::model::cpu_conv::{
    CpuTaps, CpuUpsampling, WINOGRAD_MIN_PAIRS, shifted_products, winograd_products,
};
use motion_stylizer::model::layers::{
    AdaIn, ConvLayerConfig, from_cbt, instance_norm, leaky_relu, reflect_pad_time, to_cbt, upsample_nearest2,
    xavier_conv1d,
};
use motion_stylizer::model::regressor::regressor_input;
use motion_stylizer::model::weights::{from_f16_bytes, load_bundle, save_bundle, to_f16_bytes};
use motion_stylizer::model::{
    ContentEncoder, Generator, GlobalRegressor, Model, ModelConfig, ModelError, MotionAutoencoder, MotionModel,
    NoiseRng, StyleCode, StyleEncoder, StyleSampling,
};
use motion_stylizer::train::losses::{kl_gaussians, kl_to_standard_normal, latent_smoothness, smooth_l1};

const T: usize = 32;

fn device() -> Device {
    Device::flex()
}

fn small(supervised: bool) -> ModelConfig {
    ModelConfig::scaled(0.125).with_num_styles(4).with_supervised(supervised)
}

fn features(rng: &mut NoiseRng, b: usize, c: usize, t: usize) -> Tensor<3> {
    rng.normal_tensor(b, c * t, &device()).reshape([b, c, t])
}

fn values<const D: usize>(t: Tensor<D>) -> Vec<f32> {
    t.into_data().try_into_vec_as::<f32>().unwrap()
}

fn max_abs_diff<const D: usize>(a: Tensor<D>, b: Tensor<D>) -> f32 {
    values(a).iter().zip(values(b)).map(|(x, y)| (x - y).abs()).fold(0.0, f32::max)
}

#[test]
fn paper_sizes_and_scaling() {
    let c = ModelConfig::default();
    assert_eq!((c.ae_hidden, c.ae_mid, c.latent_dim), (384, 512, 512));
    assert_eq!((c.content_hidden, c.content_dim, c.style_dim), (768, 512, 512));
    assert_eq!(c.generator_hidden, [768, 1024, 768]);
    assert_eq!(c.regressor_hidden, [512, 256, 128]);
    assert_eq!(c.classifier_hidden, [512, 768, 512, 512]);
    assert!(c.supervised && !c.vae);
    let h = ModelConfig::scaled(0.5);
    assert_eq!((h.ae_hidden, h.latent_dim, h.generator_hidden), (192, 256, [384, 512, 384]));
    let json = serde_json::to_string(&h).unwrap();
    assert_eq!(serde_json::from_str::<ModelConfig>(&json).unwrap(), h);
}

#[test]
fn output_shapes_of_every_network() {
    let dev = device();
    let cfg = small(true);
    let mut rng = NoiseRng::new(1);
    let x = features(&mut rng, 2, 260, T);
    let (d, dc, ds) = (cfg.latent_dim, cfg.content_dim, cfg.style_dim);

    let ae = MotionAutoencoder::new(&cfg, &dev);
    let z = ae.encoder.forward(x.clone().narrow(1, 0, 256));
    assert_eq!(z.mean.dims(), [2, d, T / 4]);
    assert!(z.logvar.is_none());
    assert_eq!(ae.decoder.forward(z.mean.clone()).dims(), [2, 260, T]);

    let vae = MotionAutoencoder::new(&cfg.clone().with_vae(true), &dev);
    let zv = vae.encoder.forward(x.clone().narrow(1, 0, 256));
    assert_eq!(zv.mean.dims(), [2, d, T / 4]);
    assert_eq!(zv.logvar.unwrap().dims(), [2, d, T / 4]);

    let content = ContentEncoder::new(&cfg, &dev).forward(z.mean.clone());
    assert_eq!(content.dims(), [2, dc, T / 8]);

    let label = motion_stylizer::model::layers::one_hot(&[0, 3], 4, &dev);
    let style = StyleEncoder::new(&cfg, &dev).forward(z.mean.clone(), Some(label.clone()));
    assert_eq!(style.mean.dims(), [2, ds]);
    assert_eq!(style.logvar.dims(), [2, ds]);

    let out = Generator::new(&cfg, &dev).forward(content, style.mean, Some(label));
    assert_eq!(out.dims(), [2, d, T / 4]);

    let unsup = small(false);
    let style_u = StyleEncoder::new(&unsup, &dev).forward(z.mean.clone(), None);
    assert_eq!(style_u.mean.dims(), [2, unsup.style_dim]);

    let reg_in = regressor_input(x.clone());
    assert_eq!(reg_in.dims(), [2, 254, T]);
    assert_eq!(GlobalRegressor::new(&cfg, &dev).forward(reg_in).dims(), [2, 2, T]);

    let cls = StyleClassifier::new(&cfg, &dev).forward(x.narrow(1, 0, 256));
    assert_eq!(cls.feature.dims(), [2, cfg.classifier_hidden[3]]);
    assert_eq!(cls.logits.dims(), [2, 4]);
    let norms = values(cls.feature.square().sum_dim(1));
    assert!(norms.iter().all(|n| (n - 1.0).abs() < 1e-4), "{norms:?}");
}

/// Every network treats the clips of a batch independently: a batch of three gives, clip by clip,
/// the numbers of each clip alone (the layers compute in the batch-inner layout `[C, B, T]`; a
/// mix-up of the batch and channel axes would break this).
#[test]
fn every_network_computes_each_clip_of_a_batch_on_its_own() {
    let dev = device();
    let cfg = small(true);
    let mut rng = NoiseRng::new(7);
    let x = features(&mut rng, 3, 260, T);
    let label = motion_stylizer::model::layers::one_hot(&[0, 3, 1], 4, &dev);
    let ae = MotionAutoencoder::new(&cfg, &dev);
    let content = ContentEncoder::new(&cfg, &dev);
    let style = StyleEncoder::new(&cfg, &dev);
    let generator = Generator::new(&cfg, &dev);
    let regressor = GlobalRegressor::new(&cfg, &dev);
    let classifier = StyleClassifier::new(&cfg, &dev);
    let run = |x: Tensor<3>, label: Tensor<2>| -> Vec<Vec<f32>> {
        let z = ae.encoder.forward(x.clone().narrow(1, 0, 256)).mean;
        let c = content.forward(z.clone());
        let s = style.forward(z.clone(), Some(label.clone())).mean;
        let g = generator.forward(c.clone(), s.clone(), Some(label));
        vec![
            values(ae.decoder.forward(z)),
            values(c),
            values(s),
            values(g),
            values(regressor.forward(regressor_input(x.clone()))),
            values(classifier.forward(x.narrow(1, 0, 256)).logits),
        ]
    };
    let batch = run(x.clone(), label.clone());
    for i in 0..3 {
        let alone = run(x.clone().narrow(0, i, 1), label.clone().narrow(0, i, 1));
        for (net, (all, one)) in batch.iter().zip(&alone).enumerate() {
            let n = one.len();
            let diff = all[i * n..(i + 1) * n].iter().zip(one).map(|(a, b)| (a - b).abs()).fold(0f32, f32::max);
            assert!(diff < 1e-4, "network {net}, clip {i}: {diff}");
        }
    }
}

#[test]
fn layer_helpers() {
    let dev = device();
    let x = Tensor::<3>::from_data(TensorData::new(vec![1f32, 2., 3., 4.], [1, 1, 4]), &dev);
    assert_eq!(values(reflect_pad_time(x.clone(), 1)), vec![2., 1., 2., 3., 4., 3.]);
    assert_eq!(values(upsample_nearest2(x.clone())), vec![1., 1., 2., 2., 3., 3., 4., 4.]);
    let one = Tensor::<3>::from_data(TensorData::new(vec![5f32], [1, 1, 1]), &dev);
    assert_eq!(values(reflect_pad_time(one, 1)), vec![5., 5., 5.]);
    let n = values(instance_norm(x));
    let mean: f32 = n.iter().sum::<f32>() / 4.0;
    let var: f32 = n.iter().map(|v| (v - mean).powi(2)).sum::<f32>() / 4.0;
    assert!(mean.abs() < 1e-6 && (var - 1.0).abs() < 1e-3, "{mean} {var}");
}

/// The inference convolution as matrix products gives Burn's convolution's numbers for every
/// shape the networks use (kernel 1; kernel 3 at stride 1 and 2, zero padding or none), even and
/// odd lengths, batch 1 and 3.
#[test]
fn conv_as_matrix_products_matches_burns_conv() {
    let mut rng = NoiseRng::new(3);
    for &(k, stride, pad) in &[(1, 1, 0), (3, 1, 0), (3, 1, 1), (3, 2, 0), (3, 2, 1)] {
        for &(b, t) in &[(1, 16), (3, 9), (1, 3), (2, 40)] {
            let conv = xavier_conv1d(12, 7, k, stride, pad, true, &device());
            let x = features(&mut rng, b, 12, t);
            let (ours, burn) = (conv1d_gemm(&conv, x.clone()), conv.forward(x));
            assert_eq!(ours.dims(), burn.dims(), "k{k} s{stride} p{pad} b{b} t{t}");
            let diff = max_abs_diff(ours, burn);
            assert!(diff < 1e-5, "k{k} s{stride} p{pad} b{b} t{t}: {diff}");
        }
    }
    let no_bias = xavier_conv1d(5, 2, 1, 1, 0, false, &device());
    let x = features(&mut rng, 2, 5, 8);
    assert!(max_abs_diff(conv1d_gemm(&no_bias, x.clone()), no_bias.forward(x)) < 1e-5);
}

/// Inference's upsampling convolution (the taps folded, no upsampled input built) gives the
/// upsampled convolution's numbers: batch 1 and 3, short and long clips, with and without bias,
/// the taps folded on the call or beforehand; and a whole upsampling layer (LeakyReLU after it)
/// takes it only once prepared for inference, on untracked tensors.
#[test]
fn upsampling_convolution_with_folded_taps_matches_upsample_then_conv() {
    let mut rng = NoiseRng::new(5);
    for &(b, t) in &[(1, 1), (1, 20), (3, 7), (2, 40)] {
        for bias in [true, false] {
            let conv = xavier_conv1d(12, 7, 3, 1, 1, bias, &device());
            let x = features(&mut rng, b, 12, t);
            let folded = from_cbt(upsample2_conv1d_gemm_cbt(&conv, None, to_cbt(x.clone())));
            let plain = from_cbt(conv1d_gemm_cbt(&conv, to_cbt(upsample_nearest2(x.clone()))));
            assert_eq!(folded.dims(), [b, 7, 2 * t]);
            let diff = max_abs_diff(folded.clone(), plain);
            assert!(diff < 1e-5, "b{b} t{t} bias {bias}: {diff}");
            assert!(max_abs_diff(folded.clone(), conv.forward(upsample_nearest2(x.clone()))) < 1e-5);
            let taps = fold_upsampling_taps(&conv).expect("k3, stride 1, padding 1");
            assert_eq!(taps.dims(), [14, 24]);
            let prefolded = from_cbt(upsample2_conv1d_gemm_cbt(&conv, Some(taps), to_cbt(x)));
            assert_eq!(values(prefolded), values(folded), "b{b} t{t}: the same taps, the same bytes");
        }
    }
    // The parities interleaved on the CPU (the path on flex) and in tensor operations (the path on
    // other devices): the same values in the same places, byte for byte.
    for &(c, b, t) in &[(1, 1, 1), (3, 2, 5), (7, 4, 20)] {
        let product =
            Tensor::<2>::from_data(TensorData::new(rng.normals(2 * c * b * (t + 1)), [2 * c, b * (t + 1)]), &device());
        let on_cpu = interleave_parities(product.clone(), c, b, t);
        let by_ops = interleave_parities_by_tensor_ops(product.clone(), c, b, t);
        assert_eq!(on_cpu.dims(), [c, b, 2 * t]);
        assert_eq!(values(on_cpu.clone()), values(by_ops), "c{c} b{b} t{t}");
        // Output 2s + 1 of the last channel and clip is the odd row's column s + 1.
        let p = values(product);
        let last = values(on_cpu.narrow(0, c - 1, 1).narrow(1, b - 1, 1));
        assert_eq!(last[2 * t - 1], p[(2 * c - 1) * b * (t + 1) + (b - 1) * (t + 1) + t]);
    }

    // On the CPU, Winograd's three products (`cpu_conv::upsampling_products`) with the bias and the
    // activation in the pass that combines them: the tensor path's numbers within rounding, with
    // and without the activation, for one frame, several clips and longer clips.
    for bias in [true, false] {
        let mut conv = xavier_conv1d(12, 7, 3, 1, 1, bias, &device());
        // A bias that is not zero, so that adding it shows.
        conv.bias = conv.bias.map(|b| burn::module::Param::from_tensor(b.val() + 0.25));
        let folded = fold_upsampling_taps(&conv).expect("k3, stride 1, padding 1");
        let cpu = CpuUpsampling::new(split_taps(&conv), conv.bias.as_ref().map(|b| b.val())).expect("f32 taps");
        assert_eq!(cpu.c_out(), 7);
        for &(b, t) in &[(1, 1), (3, 10), (2, 40)] {
            let x = features(&mut rng, b, 12, t);
            let by_ops = from_cbt(upsample2_conv1d_gemm_cbt(&conv, Some(folded.clone()), to_cbt(x.clone())));
            for activate in [false, true] {
                let on_cpu = upsample2_conv1d_on_cpu(&cpu, to_cbt(x.clone()), activate);
                let on_cpu = from_cbt(on_cpu.expect("f32"));
                assert_eq!(on_cpu.dims(), [b, 7, 2 * t]);
                let expected = if activate { leaky_relu(by_ops.clone()) } else { by_ops.clone() };
                let diff = max_abs_diff(on_cpu, expected);
                assert!(diff < 1e-5, "b{b} t{t} bias {bias} activate {activate}: {diff}");
            }
        }
    }
    // A whole prepared layer takes these products on flex: below.

    // Other shapes have no folded taps (and the function upsamples, then convolves).
    assert!(fold_upsampling_taps(&xavier_conv1d(4, 4, 3, 2, 1, true, &device())).is_none());
    assert!(fold_upsampling_taps(&xavier_conv1d(4, 4, 1, 1, 0, true, &device())).is_none());

    let mut layer = ConvLayerConfig::new(10, 6, 3).up().init(&device());
    let x = features(&mut rng, 2, 10, 12);
    let expected = {
        let y = conv1d_gemm(&layer.conv, upsample_nearest2(x.clone()));
        burn::tensor::activation::leaky_relu(y, 0.2)
    };
    // Not prepared: upsampled, then convolved, byte for byte.
    assert_eq!(values(layer.forward(x.clone())), values(expected.clone()));
    // Prepared (on flex): Winograd's three products, within rounding.
    layer.fold_for_inference();
    let inference = layer.forward(x.clone());
    assert_eq!(inference.dims(), [2, 6, 24]);
    // (Other sums, so some bytes differ: the prepared path did run; fixed seed, so not by chance.)
    assert_ne!(values(inference.clone()), values(expected.clone()));
    assert!(max_abs_diff(inference.clone(), expected.clone()) < 1e-5);
    // ... and they are Winograd's products with the activation, byte for byte.
    let cpu = CpuUpsampling::new(split_taps(&layer.conv), layer.conv.bias.as_ref().map(|b| b.val())).expect("f32");
    let winograd = from_cbt(upsample2_conv1d_on_cpu(&cpu, to_cbt(x.clone()), true).expect("f32"));
    assert_eq!(values(inference), values(winograd));
    // A tracked input (training's graph) never takes the folded taps: the prepared layer gives the
    // unprepared one's bytes there.
    let ad = device().autodiff();
    let unprepared = ConvLayerConfig::new(10, 6, 3).up().init(&ad).load_record(layer.clone().into_record());
    let mut prepared = unprepared.clone();
    prepared.fold_for_inference();
    let xt = || Tensor::<3>::from_data(x.clone().into_data(), &ad).require_grad();
    let y = prepared.forward(xt());
    assert!(max_abs_diff(y.clone().inner(), expected) < 1e-5);
    assert_eq!(values(y), values(unprepared.forward(xt())));
}

/// Inference's kernel-3 convolution as three products on shifted views of the clips padded side
/// by side (no columns built) gives the column product's numbers: zero padding (the convolution's
/// own) and reflection padding (the layer's, before a convolution without padding), batches of 1
/// to 6, clips of 2 to 40 frames, with and without bias; and a whole layer takes it only once
/// prepared, from `SHIFTED_MIN_BATCH` clips on, on untracked tensors.
#[test]
fn kernel3_convolution_as_shifted_products_matches_the_columns() {
    let mut rng = NoiseRng::new(8);
    for &(b, t) in &[(1, 2), (4, 3), (5, 20), (6, 40)] {
        for bias in [true, false] {
            for reflect in [false, true] {
                let conv = xavier_conv1d(12, 7, 3, 1, if reflect { 0 } else { 1 }, bias, &device());
                let x = features(&mut rng, b, 12, t);
                let padded = if reflect { reflect_pad_time(x.clone(), 1) } else { x.clone() };
                let columns = from_cbt(conv1d_gemm_cbt(&conv, to_cbt(padded.clone())));
                let taps = split_taps(&conv);
                assert_eq!(taps.dims(), [3, 7, 12]);
                let shifted = from_cbt(conv3_shifted_cbt(&conv, &taps, to_cbt(x.clone()), reflect));
                assert_eq!(shifted.dims(), [b, 7, t]);
                let diff = max_abs_diff(shifted.clone(), columns);
                assert!(diff < 1e-5, "b{b} t{t} bias {bias} reflect {reflect}: {diff}");
                assert!(max_abs_diff(shifted, conv.forward(padded)) < 1e-5, "b{b} t{t}: Burn's convolution");
            }
        }
    }

    // On the CPU, the three products accumulated into one buffer with the bias and the activation
    // (`model::cpu_conv`), below `WINOGRAD_MIN_PAIRS` pairs of output columns: the tensor path's
    // bytes where a product's sum over the input channels is one block, within rounding where
    // `gemm` splits it (600 channels). From that many pairs on, Winograd's four products: the
    // tensor path's numbers within rounding (an odd number of columns with zero padding: 7 clips
    // of 4 + 1 frames).
    for &(c_in, b, t) in &[(12, 4, 3), (600, 4, 2), (12, 7, 4), (12, 5, 20), (600, 5, 16)] {
        for reflect in [false, true] {
            let conv = xavier_conv1d(c_in, 7, 3, 1, if reflect { 0 } else { 1 }, true, &device());
            let taps = split_taps(&conv);
            let cpu = CpuTaps::new(taps.clone(), conv.bias.as_ref().map(|b| b.val())).expect("f32 taps");
            let x = features(&mut rng, b, c_in, t);
            let by_ops = from_cbt(conv3_shifted_cbt(&conv, &taps, to_cbt(x.clone()), reflect));
            let winograd = winograd_pays(b, t, reflect);
            assert_eq!(winograd, (b * if reflect { t + 2 } else { t + 1 }).div_ceil(2) >= WINOGRAD_MIN_PAIRS);
            for activate in [false, true] {
                let on_cpu = conv3_shifted_on_cpu(&cpu, to_cbt(x.clone()), reflect, activate).expect("f32 input");
                let on_cpu = from_cbt(on_cpu);
                let expected = if activate { leaky_relu(by_ops.clone()) } else { by_ops.clone() };
                assert_eq!(on_cpu.dims(), [b, 7, t]);
                let what = format!("c_in {c_in} b{b} t{t} reflect {reflect} activate {activate} winograd {winograd}");
                if c_in == 12 && !winograd {
                    assert_eq!(values(on_cpu), values(expected), "{what}");
                } else {
                    let diff = max_abs_diff(on_cpu, expected);
                    assert!(diff < if c_in == 12 { 1e-5 } else { 1e-4 }, "{what}: {diff}");
                }
            }
        }
    }
    assert!(winograd_pays(7, 4, false) && (7 * 5) % 2 == 1, "an odd number of columns is tested");
    // Winograd's products on the tightest rows (`ld = n + 2`, odd and even `n`): the shifted
    // products' numbers; rows shorter than that are refused.
    for n in [33, 34] {
        let conv = xavier_conv1d(9, 5, 3, 1, 1, true, &device());
        let cpu = CpuTaps::new(split_taps(&conv), conv.bias.as_ref().map(|b| b.val())).expect("f32 taps");
        let ld = n + 2;
        let x = rng.normals(9 * ld);
        let direct = shifted_products(&cpu, &x, ld, n, true).expect("fits");
        let fast = winograd_products(&cpu, &x, ld, n, true).expect("fits");
        assert_eq!(fast.len(), 5 * n);
        let diff = direct.iter().zip(&fast).map(|(a, b)| (a - b).abs()).fold(0.0, f32::max);
        assert!(diff < 1e-5, "n {n}: {diff}");
        assert!(winograd_products(&cpu, &x[..9 * ld - 1], ld, n, true).is_none());
        assert!(winograd_products(&cpu, &x, n + 1, n, true).is_none());
    }

    for reflect in [false, true] {
        let config = ConvLayerConfig::new(10, 6, 3);
        let mut layer = if reflect { config } else { config.zero_padded() }.init(&device());
        let x = features(&mut rng, SHIFTED_MIN_BATCH, 10, 12);
        let expected = layer.forward(x.clone());
        layer.fold_for_inference();
        let inference = layer.forward(x.clone());
        assert_eq!(inference.dims(), [SHIFTED_MIN_BATCH, 6, 12]);
        // (Other sums, so some bytes differ: the shifted path did run; fixed seed, so not by chance.)
        assert_ne!(values(inference.clone()), values(expected.clone()), "reflect {reflect}");
        assert!(max_abs_diff(inference.clone(), expected.clone()) < 1e-5);
        // The activation goes over the product with its padding frames, then the frames are cut:
        // the activation of the cut frames (Winograd's products here: within rounding).
        assert!(winograd_pays(SHIFTED_MIN_BATCH, 12, reflect));
        let shifted = from_cbt(conv3_shifted_cbt(&layer.conv, &split_taps(&layer.conv), to_cbt(x.clone()), reflect));
        assert!(max_abs_diff(inference.clone(), leaky_relu(shifted)) < 1e-5, "reflect {reflect}");
        let taps = split_taps(&layer.conv);
        let cpu = CpuTaps::new(taps, layer.conv.bias.as_ref().map(|b| b.val())).expect("f32 taps");
        let winograd = from_cbt(conv3_shifted_on_cpu(&cpu, to_cbt(x.clone()), reflect, true).expect("f32"));
        assert_eq!(values(inference), values(winograd), "reflect {reflect}: the layer took Winograd's products");
        // Below the batch threshold: the columns, byte for byte.
        let small = x.clone().narrow(0, 0, SHIFTED_MIN_BATCH - 1);
        assert_eq!(values(layer.forward(small)), values(expected.clone().narrow(0, 0, SHIFTED_MIN_BATCH - 1)));
        // A tracked input never takes it.
        let ad = device().autodiff();
        let xt = Tensor::<3>::from_data(x.clone().into_data(), &ad).require_grad();
        let unprepared = ConvLayerConfig::new(10, 6, 3);
        let unprepared = if reflect { unprepared } else { unprepared.zero_padded() }
            .init(&ad)
            .load_record(layer.clone().into_record());
        let mut prepared = unprepared.clone();
        prepared.fold_for_inference();
        assert_eq!(values(prepared.forward(xt.clone())), values(unprepared.forward(xt)));
    }
}

#[test]
fn adain_at_initialisation_is_instance_norm() {
    let dev = device();
    let mut rng = NoiseRng::new(2);
    let adain = AdaIn::new(6, 5, &dev);
    let x = features(&mut rng, 3, 6, 10) * 3.0 + 1.5;
    // γ, β come from a linear layer whose bias starts at (1, 0): with a zero conditioning vector
    // AdaIN is exactly instance norm.
    let zero = Tensor::<2>::zeros([3, 5], &dev);
    assert!(max_abs_diff(adain.forward(x.clone(), zero), instance_norm(x.clone())) < 1e-6);
    // A non-zero style moves it.
    let cond = rng.normal_tensor(3, 5, &dev);
    assert!(max_abs_diff(adain.forward(x.clone(), cond), instance_norm(x)) > 1e-2);
}

#[test]
fn generator_output_depends_on_the_style_code() {
    let dev = device();
    for supervised in [true, false] {
        let cfg = small(supervised);
        let mut rng = NoiseRng::new(3);
        let generator = Generator::new(&cfg, &dev);
        let content = features(&mut rng, 2, cfg.content_dim, 4);
        let label = supervised.then(|| motion_stylizer::model::layers::one_hot(&[1, 2], 4, &dev));
        let s1 = rng.normal_tensor(2, cfg.style_dim, &dev);
        let s2 = rng.normal_tensor(2, cfg.style_dim, &dev);
        let a = generator.forward(content.clone(), s1.clone(), label.clone());
        let b = generator.forward(content.clone(), s2, label.clone());
        let a2 = generator.forward(content, s1, label);
        assert!(max_abs_diff(a.clone(), b) > 1e-3);
        assert_eq!(values(a), values(a2));
    }
    // In a supervised model the label alone changes the output too.
    let cfg = small(true);
    let stylizer = Model::seeded(cfg.clone(), &dev, 1);
    let mut rng = NoiseRng::new(4);
    let content = features(&mut rng, 1, cfg.content_dim, 4);
    let code = rng.normal_tensor(1, cfg.style_dim, &dev);
    let a = stylizer.generate(content.clone(), &StyleCode { code: code.clone(), labels: Some(vec![0]) }).unwrap();
    let b = stylizer.generate(content, &StyleCode { code, labels: Some(vec![3]) }).unwrap();
    assert!(max_abs_diff(a, b) > 1e-4);
}

#[test]
fn length_channel_and_label_rules_are_typed_errors() {
    let dev = device();
    let sup = Model::seeded(small(true), &dev, 2);
    let unsup = Model::seeded(small(false), &dev, 3);
    let mut rng = NoiseRng::new(5);
    for bad in [12, 20, 33, 36] {
        let x = features(&mut rng, 1, 260, bad);
        assert_eq!(sup.encode(x.clone()).unwrap_err(), ModelError::FrameCount { frames: bad, multiple: 8 });
        let style = sup.style_from_label(&[1], &mut rng).unwrap();
        assert!(matches!(sup.stylize(x, &style), Err(ModelError::FrameCount { .. })));
    }
    // Latent of odd length: no content code.
    let z = features(&mut rng, 1, sup.config.latent_dim, 3);
    assert_eq!(sup.content(z).unwrap_err(), ModelError::LatentLength { len: 3 });
    // Wrong channels.
    let x = features(&mut rng, 1, 100, 32);
    assert!(matches!(sup.encode(x), Err(ModelError::Channels { got: 100, .. })));
    // Labels.
    let z = features(&mut rng, 2, sup.config.latent_dim, 8);
    assert!(matches!(sup.style_distribution(z.clone(), None), Err(ModelError::Label(_))));
    assert!(matches!(sup.style_distribution(z.clone(), Some(&[0, 4])), Err(ModelError::Label(_))));
    assert!(matches!(sup.style_distribution(z.clone(), Some(&[0])), Err(ModelError::BatchSize { .. })));
    assert!(matches!(unsup.style_distribution(z.clone(), Some(&[0, 1])), Err(ModelError::Label(_))));
    assert!(matches!(sup.style_from_prior(1, &mut rng), Err(ModelError::Label(_))));
    assert!(matches!(unsup.style_from_label(&[0], &mut rng), Err(ModelError::Label(_))));
    assert!(unsup.style_distribution(z, None).is_ok());
    // Every multiple of 8 works end to end, the shortest included.
    for t in [8, 16, 32, 40] {
        let x = features(&mut rng, 1, 260, t);
        let style = unsup.style_from_prior(1, &mut rng).unwrap();
        assert_eq!(unsup.stylize(x, &style).unwrap().dims(), [1, 260, t]);
    }
}

#[test]
fn loss_functions() {
    let dev = device();
    let a = Tensor::<1>::from_floats([0.0, 0.0, 0.0, 0.0], &dev);
    let b = Tensor::<1>::from_floats([0.5, -0.5, 2.0, -3.0], &dev);
    // 0.125, 0.125, 1.5, 2.5 → mean 1.0625
    let v = smooth_l1(a.clone(), b).into_scalar::<f32>();
    assert!((v - 1.0625).abs() < 1e-6, "{v}");
    let zeros = Tensor::<2>::zeros([2, 3], &dev);
    assert!(kl_to_standard_normal(zeros.clone(), zeros.clone()).into_scalar::<f32>().abs() < 1e-7);
    let mut rng = NoiseRng::new(6);
    let mu = rng.normal_tensor(2, 3, &dev);
    let lv = rng.normal_tensor(2, 3, &dev);
    assert!(kl_gaussians(mu.clone(), lv.clone(), mu.clone(), lv.clone()).into_scalar::<f32>().abs() < 1e-6);
    // KL(N(μ,σ²) ‖ N(0,1)) equals the general formula against (0, 0).
    let k1 = kl_to_standard_normal(mu.clone(), lv.clone()).into_scalar::<f32>();
    let k2 = kl_gaussians(mu, lv, zeros.clone(), zeros).into_scalar::<f32>();
    assert!((k1 - k2).abs() < 1e-5 && k1 > 0.0);
    let z = Tensor::<3>::from_data(TensorData::new(vec![0f32, 1., 3., 3.], [1, 1, 4]), &dev);
    assert!((latent_smoothness(z).into_scalar::<f32>() - 1.0).abs() < 1e-6);
}

#[test]
fn noise_is_seeded_and_standard_normal() {
    let a = NoiseRng::new(42).normals(20000);
    assert_eq!(a, NoiseRng::new(42).normals(20000));
    assert_ne!(a, NoiseRng::new(43).normals(20000));
    let mean = a.iter().map(|&v| v as f64).sum::<f64>() / a.len() as f64;
    let var = a.iter().map(|&v| (v as f64 - mean).powi(2)).sum::<f64>() / a.len() as f64;
    assert!(mean.abs() < 0.03 && (var - 1.0).abs() < 0.05, "{mean} {var}");
}

fn run_all_paths(stylizer: &Model, seed: u64) -> Vec<Vec<f32>> {
    let mut rng = NoiseRng::new(seed);
    let content = features(&mut rng, 2, 260, T);
    let style_motion = features(&mut rng, 2, 260, T);
    let mut out = Vec::new();
    let latent = stylizer.encode(style_motion).unwrap();
    let labels = stylizer.config.supervised.then_some(&[1usize, 2][..]);
    let mean = stylizer.style_from_motion(latent.clone(), labels, StyleSampling::Mean).unwrap();
    let sample = stylizer.style_from_motion(latent, labels, StyleSampling::Sample(&mut rng)).unwrap();
    let prior = if stylizer.config.supervised {
        stylizer.style_from_label(&[0, 3], &mut rng).unwrap()
    } else {
        stylizer.style_from_prior(2, &mut rng).unwrap()
    };
    for style in [mean, sample, prior] {
        out.push(values(stylizer.stylize(content.clone(), &style).unwrap()));
    }
    out
}

#[test]
fn same_seed_gives_bit_identical_outputs() {
    for supervised in [true, false] {
        let build = || Model::seeded(small(supervised), &device(), 11);
        let (s1, s2) = (build(), build());
        let a = run_all_paths(&s1, 9);
        assert_eq!(a, run_all_paths(&s1, 9), "same model, same seed");
        assert_eq!(a, run_all_paths(&s2, 9), "same init seed, same inference seed");
        let b = run_all_paths(&s1, 10);
        assert_ne!(a, b, "a different seed gives different inputs and samples");
        assert_ne!(a[0], a[1], "a sampled style differs from the posterior mean");
        assert!(a.iter().flatten().all(|v| v.is_finite()));
    }
}

#[test]
fn f16_weights_round_trip() {
    let dev = device();
    for cfg in [small(true), small(false).with_vae(true)] {
        let model = MotionModel::seeded(&cfg, &dev, 4);
        let stylizer = Model::new(cfg.clone(), model.clone());
        let bytes = save_bundle(&cfg, model.clone()).unwrap();
        let params = model.num_params();
        // f16: 2 bytes per parameter plus a small header and the per-tensor index.
        assert!(bytes.len() < params * 2 + 16 * 1024, "{} bytes for {params} params", bytes.len());
        assert!(bytes.len() >= params * 2);
        let (cfg2, model2) = load_bundle(&bytes, &dev).unwrap();
        assert_eq!(cfg2, cfg);
        let loaded = Model::new(cfg2, model2);
        let a = run_all_paths(&stylizer, 3);
        let b = run_all_paths(&loaded, 3);
        for (x, y) in a.iter().zip(&b) {
            let scale = x.iter().fold(0f32, |m, v| m.max(v.abs())).max(1.0);
            let err = x.iter().zip(y).map(|(p, q)| (p - q).abs()).fold(0.0, f32::max);
            assert!(err < 2e-2 * scale, "f16 round trip error {err} (scale {scale})");
        }
        // Loaded weights are exactly the f16 values: saving again gives the same bytes.
        let again = save_bundle(&loaded.config, loaded.nets.clone()).unwrap();
        assert_eq!(bytes.len(), again.len());
    }
    // One network alone, and bad bytes.
    let cfg = small(true);
    let generator = motion_stylizer::model::init::seeded_xavier(Generator::new(&cfg, &dev), 5);
    let bytes = to_f16_bytes(generator.clone()).unwrap();
    let loaded = from_f16_bytes(Generator::new(&cfg, &dev), &bytes).unwrap();
    let w0 = values(generator.out.conv.weight.val());
    let w1 = values(loaded.out.conv.weight.val());
    assert!(w0.iter().zip(&w1).all(|(a, b)| (a - b).abs() <= a.abs() * 1e-3 + 1e-6));
    assert!(from_f16_bytes(ContentEncoder::new(&cfg, &dev), &bytes).is_err());
    assert!(load_bundle(b"garbage", &dev).is_err());
}

/// Issue 14, the posture path (`ModelConfig::content_posture`): the content code carries the
/// content latent's mean over time in its extra channels; a network grown from weights without
/// the path (`train stylizer --from … --content-posture`) starts with the map at zero and gives
/// those weights' outputs; a map that is not zero adds `W·mean` at every step of the output.
#[test]
fn the_posture_path_starts_at_zero_and_adds_a_map_of_the_contents_mean() {
    use burn::nn::{Initializer, LinearConfig};
    use motion_stylizer::model::Stylizer;
    use motion_stylizer::model::init::seeded_xavier;
    let dev = device();
    let off = small(true);
    let on = off.clone().with_content_posture(true);
    assert_eq!(on.content_code_dim(), off.content_dim + off.latent_dim);
    let old = seeded_xavier(Stylizer::new(&off, &dev), 1);
    let (mut grown, added) =
        motion_stylizer::train::finetune::grow(&old, seeded_xavier(Stylizer::new(&on, &dev), 2)).unwrap();
    assert!(added.iter().any(|p| p.starts_with("generator.posture")), "{added:?}");

    let mut rng = NoiseRng::new(3);
    let z = features(&mut rng, 2, off.latent_dim, 8);
    let code = grown.content_encoder.forward(z.clone());
    assert_eq!(code.dims(), [2, on.content_code_dim(), 4]);
    let plain = old.content_encoder.forward(z.clone());
    assert_eq!(max_abs_diff(code.clone().narrow(1, 0, off.content_dim), plain.clone()), 0.0);
    let mean = z.mean_dim(2);
    let posture = code.clone().narrow(1, off.content_dim, off.latent_dim);
    assert!(max_abs_diff(posture, mean.clone().repeat_dim(2, 4)) < 1e-6);

    let style = rng.normal_tensor(2, off.style_dim, &dev);
    let label = || Some(motion_stylizer::model::layers::one_hot(&[0, 3], 4, &dev));
    let before = old.generator.forward(plain, style.clone(), label());
    let at_zero = grown.generator.forward(code.clone(), style.clone(), label());
    assert_eq!(max_abs_diff(at_zero, before.clone()), 0.0, "a zero map adds nothing");

    grown.generator.posture = Some(
        LinearConfig::new(off.latent_dim, off.latent_dim)
            .with_bias(false)
            .with_initializer(Initializer::Constant { value: 0.01 })
            .init(&dev),
    );
    let moved = grown.generator.forward(code, style, label());
    let [b, d, l] = before.dims();
    let expected = (mean.sum_dim(1) * 0.01).reshape([b, 1, 1]).repeat_dim(1, d).repeat_dim(2, l);
    assert!(max_abs_diff(moved - before, expected) < 1e-5);
}
