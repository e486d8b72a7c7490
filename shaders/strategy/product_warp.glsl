// Strategy "product-warp": warp composition (Hart, Pharr, Müller, Lopes, McGuire & Shirley 2020, "Practical
// Product Sampling by Fitting and Composing Warps"): a head warp tabulated per pixel as a piecewise-constant
// table of f cos over a uniform grid of env-hier's unit square, composed with env-hier's warp (the tail), so
// p(wi) = p_head(u) p_env-hier(wi) with u = env-hier's inverse of wi. The same estimator as `product`, with
// the grid's cells for nodes (lib/product_sampling.glsl).
#define PRODUCT_UNIFORM_GRID 1
#include "strategy/product.glsl"
