//! [`StyleSpec`]: an owned description of a [`StyleSource`], built from JS and resolved against
//! the weights (label names → labels) when a stylization runs.

use std::rc::Rc;

use wasm_bindgen::prelude::*;

use super::error::stylize_error;
use super::motion::ImportedMotion;
use crate::Motion;
use crate::stylize::{MAX_MIX_DEPTH, StyleSource, StylizeError, Weights};

#[derive(Debug)]
enum Node {
    Motion {
        motion: Rc<Motion>,
        label: Option<String>,
    },
    Label(String),
    Prior,
    Mix {
        a: Rc<Node>,
        b: Rc<Node>,
        t: f32,
    },
    /// No style: a body part keeps the content's own motion (only a part's choice).
    Content,
}

/// Where the style comes from: a label, a reference motion (with its label for the supervised
/// model), the prior, or a mix `(1 − t)·a + t·b` of two of them.
#[wasm_bindgen]
#[derive(Clone)]
pub struct StyleSpec {
    node: Rc<Node>,
    /// Nesting of mixes (0 for a plain source), capped at [`MAX_MIX_DEPTH`] when built so that
    /// nothing recursive ever walks a deep chain.
    depth: usize,
}

#[wasm_bindgen]
impl StyleSpec {
    /// Whether this is [`StyleSpec::content`].
    pub(super) fn is_content(&self) -> bool {
        matches!(*self.node, Node::Content)
    }

    /// Label-based: the style called `name` (checked when it is used).
    pub fn label(name: String) -> StyleSpec {
        StyleSpec { node: Rc::new(Node::Label(name)), depth: 0 }
    }

    /// Motion-based: the style of `reference`; `label` is its style label (the supervised model
    /// needs it, the unsupervised one refuses it).
    pub fn motion(reference: &ImportedMotion, label: Option<String>) -> StyleSpec {
        StyleSpec { node: Rc::new(Node::Motion { motion: Rc::clone(&reference.motion), label }), depth: 0 }
    }

    /// Prior-based: a random style (supervised model: with a random label).
    pub fn prior() -> StyleSpec {
        StyleSpec { node: Rc::new(Node::Prior), depth: 0 }
    }

    /// For a body part of `Engine.stylizeParts`: keep the content's own motion there.
    pub fn content() -> StyleSpec {
        StyleSpec { node: Rc::new(Node::Content), depth: 0 }
    }

    /// `(1 − t)·a + t·b`, `t` in [0, 1] (checked when it is used). Error `BAD_REQUEST` when mixes
    /// would nest deeper than the pipeline's limit.
    pub fn mix(a: &StyleSpec, b: &StyleSpec, t: f64) -> Result<StyleSpec, JsValue> {
        let depth = a.depth.max(b.depth) + 1;
        if depth > MAX_MIX_DEPTH {
            return Err(stylize_error(&StylizeError::MixTooDeep { max: MAX_MIX_DEPTH }));
        }
        let node = Node::Mix { a: Rc::clone(&a.node), b: Rc::clone(&b.node), t: t as f32 };
        Ok(StyleSpec { node: Rc::new(node), depth })
    }
}

impl StyleSpec {
    /// The pipeline's source, label names looked up in `weights` (`UNKNOWN_LABEL`).
    pub(super) fn source<'a>(&'a self, weights: &Weights) -> Result<StyleSource<'a>, StylizeError> {
        resolve(&self.node, weights)
    }
}

fn resolve<'a>(node: &'a Node, weights: &Weights) -> Result<StyleSource<'a>, StylizeError> {
    Ok(match node {
        Node::Motion { motion, label } => {
            StyleSource::Motion { motion, label: label.as_deref().map(|l| weights.style(l)).transpose()? }
        }
        Node::Label(name) => StyleSource::Label(weights.style(name)?),
        Node::Prior => StyleSource::Prior,
        Node::Mix { a, b, t } => StyleSource::mix(resolve(a, weights)?, resolve(b, weights)?, *t),
        Node::Content => {
            return Err(StylizeError::Parts(
                "'content' keeps a body part's own motion: it is no style to stylize or mix with".into(),
            ));
        }
    })
}
