// Strategy "product-warp": warp composition (Hart, Pharr, Müller, Lopes, McGuire & Shirley 2020, "Practical
// Product Sampling by Fitting and Composing Warps"): a head warp tabulated per pixel as a piecewise-constant
// table of f cos over a uniform grid of env-hier's unit square, composed with env-hier's warp (the tail), so
// p(wi) = p_head(u) p_env-hier(wi) with u = env-hier's inverse of wi. The same estimator as `product`, with
// the grid's cells for nodes (lib/product_sampling.glsl). `product-warp-ot` composes with env-ot's warp
// instead (its builder defines PRODUCT_TAIL_ENV_OT; the pdf sums over a split sun's two preimages).
#define PRODUCT_UNIFORM_GRID 1
#include "strategy/product.glsl"
