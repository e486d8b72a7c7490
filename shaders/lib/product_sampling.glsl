// Product sampling of environment x BRDF over env-hier's unit square, for the `product` strategies
// (engine/sampling/product/env_hier_product.h documents the method and holds the CPU twin, EnvProductSampler). Needs the
// env technique env-hier, whose builder also provides the nodes' tables and PRODUCT_* defines. The nodes are a
// pyramid level (default) or, with PRODUCT_UNIFORM_GRID defined by the strategy part before including this
// file, a uniform grid over u (warp composition, `product-warp`). With PRODUCT_TAIL_ENV_OT (defined by
// envOtProductTechniqueData, engine/sampling/product/env_ot_product.h) the grid is over env-ot's unit square instead
// (`product-warp-ot`), whose warp reaches a split sun's texels twice: the pdf sums over both preimages.
//
// productPrepare(s), once per shading point: weights w_j = (1 - d) E_j F_j / sum_k E_k F_k + d E_j over the
// level's nodes (E_j the node's env-hier probability, F_j = mean_rgb(f) cos at the node's direction closest to
// the mirror direction of wo, d = PRODUCT_DEFENSIVE),
// kept as 16-bit running sums per row (gProductColumnSums) and over rows (gProductRowSums; kProductFullScale
// gives the rule). With PRODUCT_TABLE_BINDING (the host's choice when the image's tables fit
// PRODUCT_TABLE_CHUNKS buffers: engine/render/renderer.cpp) the first dispatch after a restart
// (frame.sampleOffset 0) also stores a pixel's sums in its chunk, two per word, and every later dispatch of the
// accumulation samples from the stored sums instead of evaluating the BRDF at every node again (once per
// accumulation, not once per dispatch of at most 256 samples): a dispatch of many samples copies them into
// private memory and scans them, one of few samples reads the rows' sums and then binary-searches the chosen
// row's words in the buffer. productSample chooses a row
// by u.y and a node in it by u.x, rescales u inside the choice, fills the node's rectangle in u with it and lets
// env-hier's descent (envSample) finish, so pdf = P(j) / E_j * p_env-hier, with P(j) computed from the same
// sums in sampling and in productPdf.
#ifndef IBLX_LIB_PRODUCT_SAMPLING
#define IBLX_LIB_PRODUCT_SAMPLING
#extension GL_EXT_control_flow_attributes : require
#include "lib/latlong.glsl"
#include "lib/table.glsl"

#ifdef PRODUCT_UNIFORM_GRID
#define PRODUCT_NODES_X PRODUCT_GRID_WIDTH
#define PRODUCT_NODES_Y PRODUCT_GRID_ROWS
// Per cell (row-major): the direction at the centre of its image under env-hier, with the cosine of the
// image's angular radius.
IBLX_TABLE(productGridCenters, 4);
vec4 productNodeCenter(uint j) { return tableVec4(productGridCenters, j); }
vec4 productNodeRect(uint j) {
  uvec2 c = uvec2(j % PRODUCT_NODES_X, j / PRODUCT_NODES_X);
  return vec4(vec2(c), vec2(c + 1u)) / vec4(PRODUCT_NODES_X, PRODUCT_NODES_Y, PRODUCT_NODES_X, PRODUCT_NODES_Y);
}
uvec2 productCellOf(vec2 u) {
  return min(uvec2(max(u, vec2(0.0)) * vec2(PRODUCT_NODES_X, PRODUCT_NODES_Y)),
             uvec2(PRODUCT_NODES_X - 1u, PRODUCT_NODES_Y - 1u));
}
#ifdef PRODUCT_TAIL_ENV_OT
#include "lib/env_ot_inverse.glsl"
#else
// The cell of u = env-hier's inverse of wi (its texel's rectangle, and wi's place in the texel).
uvec2 productNodeOf(vec3 wi) {
  ivec2 texel = directionToTexel(wi);
  vec4 rect = hierTexelRect(texel);
  return productCellOf(rect.xy + directionToTexelOffset(wi, texel) * rect.zw);
}
#endif
#else
#define PRODUCT_NODES_X PRODUCT_WIDTH
#define PRODUCT_NODES_Y PRODUCT_ROWS
// Per node (row-major): its rectangle in u (minX, minY, maxX, maxY), and the direction at its centre
// (environment frame) with the cosine of its angular radius.
IBLX_TABLE(productNodeRects, 4);
IBLX_TABLE(productNodeCenters, 4);
vec4 productNodeRect(uint j) { return tableVec4(productNodeRects, j); }
vec4 productNodeCenter(uint j) { return tableVec4(productNodeCenters, j); }
uvec2 productNodeOf(vec3 wi) { return uvec2(directionToTexel(wi)) / PRODUCT_TEXELS_PER_NODE; }
#endif

#ifdef IBLX_RECORD_SAMPLES
// The last productSample's choice, for the sample record (lib/sample_record.glsl, RECORD_PRODUCT_NODE);
// columns is 0 when it chose nothing.
struct ProductChoice {
  uint node, columns, rows;
  float probability;
  vec4 nodeUv;  // the node on the lat-long map when it is a block of texels, else 0
};
ProductChoice gProductChosen;
#ifdef PRODUCT_UNIFORM_GRID
vec4 productNodeMapUv(uint j) { return vec4(0.0); }  // a cell of the tail's square: no map rectangle
#else
vec4 productNodeMapUv(uint j) {
  uvec2 size = uvec2(envSize());
  uvec2 first = uvec2(j % PRODUCT_NODES_X, j / PRODUCT_NODES_X) * PRODUCT_TEXELS_PER_NODE;
  return vec4(vec2(min(first, size)), vec2(min(first + PRODUCT_TEXELS_PER_NODE, size))) / vec4(size, size);
}
#endif
#endif

const uint kProductNodes = PRODUCT_NODES_X * PRODUCT_NODES_Y;
// The table's running sums, over the rows' totals and within each row, are kept as 16-bit integers: for
// weights w_1..w_n with float running sums r_i and total W, of which m are positive,
//   q_i = min(round(r_i / W (65535 - m)), 65535 - m) + (the positive weights among w_1..w_i),
// so every positive weight keeps at least one step, q_n = 65535 when W > 0 (all 0 when W = 0), and
// P(row y) P(node x | y) = (q_y - q_{y-1}) / 65535 * (q_x - q_{x-1}) / 65535. Sampling and productPdf read
// the same integers, so the pdf stays exact; the quantization halves the stored table, whose loads are what
// a sample of the stored table costs (docs/BENCHMARKS.md, "Product strategies").
const float kProductFullScale = 65535.0;
float gProductColumnSums[kProductNodes];  // per row: its nodes' quantized running sums, as floats
float gProductRowSums[PRODUCT_NODES_Y];   // the rows' quantized running sums, as floats
// Replaces sums[first], ..., sums[first + count - 1], weights of total `total` of which `positive` are > 0,
// by their quantized running sums (see kProductFullScale; the float running sum is summed as `total` was, so
// running / total <= 1).
#define PRODUCT_QUANTIZE(sums, first, count, total, positive)                                      \
  {                                                                                                \
    float steps = kProductFullScale - float(positive), running = 0.0;                              \
    uint counted = 0u;                                                                             \
    [[dont_unroll]] for (uint i = 0u; i < count; ++i) {                                            \
      float weight = sums[first + i];                                                              \
      running += weight;                                                                           \
      counted += weight > 0.0 ? 1u : 0u;                                                           \
      sums[first + i] = total > 0.0 ? min(round(running / total * steps), steps) + float(counted) : 0.0; \
    }                                                                                              \
  }
#ifdef PRODUCT_TABLE_BINDING
// PRODUCT_TABLE_STRIDE words per pixel, pixels row-major, PRODUCT_TABLE_PIXELS_PER_CHUNK pixels per buffer:
// integrate.comp's invocation (x, y) shades pixel (x, y) in the image mode that binds these buffers. A pixel's
// block holds the rows' running sums first, so a dispatch of few samples reads them from one cache line, then
// each row's, two per word (the even one in the low half; an odd count's padding half is 0xffff).
layout(std430, set = 0, binding = PRODUCT_TABLE_BINDING) buffer ProductTableData0 { uint productTables0[]; };
#if PRODUCT_TABLE_CHUNKS > 1
layout(std430, set = 0, binding = PRODUCT_TABLE_BINDING + 1) buffer ProductTableData1 { uint productTables1[]; };
#endif
#if PRODUCT_TABLE_CHUNKS > 2
layout(std430, set = 0, binding = PRODUCT_TABLE_BINDING + 2) buffer ProductTableData2 { uint productTables2[]; };
#endif
#if PRODUCT_TABLE_CHUNKS > 3
layout(std430, set = 0, binding = PRODUCT_TABLE_BINDING + 3) buffer ProductTableData3 { uint productTables3[]; };
#endif
#if PRODUCT_TABLE_CHUNKS > 4
#error "PRODUCT_TABLE_CHUNKS above kProductTableMaxChunks (engine/scene/kernel_prelude.h)"
#endif
// Words of the rows' sums and of one row's; the builders check that a pixel's block fits
// PRODUCT_TABLE_STRIDE (productTableWords, engine/sampling/product/env_hier_product.h).
const uint kProductRowSumWords = (PRODUCT_NODES_Y + 1u) / 2u;
const uint kProductRowWords = (PRODUCT_NODES_X + 1u) / 2u;
// The pixel's place: its chunk and the offset of its block there (set by productPrepare).
uint gProductTableChunk = 0u, gProductTableAt = 0u;
// PRODUCT_TABLE_ON_CHUNK(OP) runs OP(the pixel's chunk's array): the one chain over the chunks.
#if PRODUCT_TABLE_CHUNKS > 1
#define PRODUCT_TABLE_CHUNK_1(OP) else if (gProductTableChunk == 1u) { OP(productTables1) }
#else
#define PRODUCT_TABLE_CHUNK_1(OP)
#endif
#if PRODUCT_TABLE_CHUNKS > 2
#define PRODUCT_TABLE_CHUNK_2(OP) else if (gProductTableChunk == 2u) { OP(productTables2) }
#else
#define PRODUCT_TABLE_CHUNK_2(OP)
#endif
#if PRODUCT_TABLE_CHUNKS > 3
#define PRODUCT_TABLE_CHUNK_3(OP) else if (gProductTableChunk == 3u) { OP(productTables3) }
#else
#define PRODUCT_TABLE_CHUNK_3(OP)
#endif
#define PRODUCT_TABLE_ON_CHUNK(OP)                                                                      \
  if (gProductTableChunk == 0u) {                                                                     \
    OP(productTables0)                                                                                \
  }                                                                                                   \
  PRODUCT_TABLE_CHUNK_1(OP) PRODUCT_TABLE_CHUNK_2(OP) PRODUCT_TABLE_CHUNK_3(OP)

#define PRODUCT_TABLE_READ(table) word = table[at];
// The word at `at` of the pixel's block.
uint productStoredWord(uint at) {
  uint word = 0u;
  at += gProductTableAt;
  PRODUCT_TABLE_ON_CHUNK(PRODUCT_TABLE_READ)
  return word;
}
// Row y's quantized running sum up to node j.
float productStoredSum(uint j) {
  uint y = j / PRODUCT_NODES_X, x = j - y * PRODUCT_NODES_X;
  uint word = productStoredWord(kProductRowSumWords + y * kProductRowWords + (x >> 1u));
  return float(bitfieldExtract(word, int((x & 1u) * 16u), 16));
}
// PRODUCT_STORE_PAIRS(table, at, sums, first, count, words): `count` private sums from sums[first] on, packed
// into `words` words of the pixel's block from `at` on.
#define PRODUCT_STORE_PAIRS(table, at, sums, first, count, words)                               \
  [[dont_unroll]] for (uint w = 0u; w < words; ++w) {                                          \
    uint high = 2u * w + 1u < count ? uint(sums[first + 2u * w + 1u]) : 0xffffu;               \
    table[gProductTableAt + at + w] = uint(sums[first + 2u * w]) | (high << 16u);              \
  }
#define PRODUCT_LOAD_PAIRS(table, at, sums, first, count, words)                                \
  [[dont_unroll]] for (uint w = 0u; w < words; ++w) {                                          \
    uint word = table[gProductTableAt + at + w];                                               \
    sums[first + 2u * w] = float(word & 0xffffu);                                              \
    if (2u * w + 1u < count) sums[first + 2u * w + 1u] = float(word >> 16u);                   \
  }
#define PRODUCT_TABLE_STORE(table)                                                                          \
  PRODUCT_STORE_PAIRS(table, 0u, gProductRowSums, 0u, PRODUCT_NODES_Y, kProductRowSumWords)                 \
  [[dont_unroll]] for (uint y = 0u; y < PRODUCT_NODES_Y; ++y) {                                             \
    PRODUCT_STORE_PAIRS(table, kProductRowSumWords + y * kProductRowWords, gProductColumnSums,              \
                        y * PRODUCT_NODES_X, PRODUCT_NODES_X, kProductRowWords)                             \
  }
#define PRODUCT_TABLE_LOAD(table)                                                                           \
  [[dont_unroll]] for (uint y = 0u; y < PRODUCT_NODES_Y; ++y) {                                             \
    PRODUCT_LOAD_PAIRS(table, kProductRowSumWords + y * kProductRowWords, gProductColumnSums,               \
                       y * PRODUCT_NODES_X, PRODUCT_NODES_X, kProductRowWords)                              \
  }
#define PRODUCT_TABLE_LOAD_ROW_SUMS(table) \
  PRODUCT_LOAD_PAIRS(table, 0u, gProductRowSums, 0u, PRODUCT_NODES_Y, kProductRowSumWords)
void productTableLocate(uvec2 pixel) {
  uint index = pixel.y * frame.width + pixel.x;
  gProductTableChunk = index / PRODUCT_TABLE_PIXELS_PER_CHUNK;
  gProductTableAt = (index - gProductTableChunk * PRODUCT_TABLE_PIXELS_PER_CHUNK) * PRODUCT_TABLE_STRIDE;
}
// Stores the private table into the pixel's chunk, or loads its rows' sums and, with `rows`, every row's.
void productTableStore() { PRODUCT_TABLE_ON_CHUNK(PRODUCT_TABLE_STORE) }
void productTableLoad(bool rows) {
  PRODUCT_TABLE_ON_CHUNK(PRODUCT_TABLE_LOAD_ROW_SUMS)
  if (rows) {
    PRODUCT_TABLE_ON_CHUNK(PRODUCT_TABLE_LOAD)
  }
}
// The node of row y whose quantized interval [start, end) holds t in [0, kProductFullScale), from the
// stored row: a binary search over the row's words by their high halves (the last word's is above every
// target: the row's last running sum 65535, or an odd row's padding), then the word's low half decides.
// Each step is one load, and the interval's ends come from the words it loaded: the high half of the last
// word found below t, and the word the search ends on.
uint productStoredChoice(uint y, float t, out float start, out float end) {
  uint first = kProductRowSumWords + y * kProductRowWords;
  uint lower = 0u, len = kProductRowWords - 1u, upperWord = 0u;
  bool haveUpper = false;
  start = 0.0;
  while (len > 0u) {
    uint step = len >> 1u;
    uint word = productStoredWord(first + lower + step);
    float high = float(word >> 16u);
    if (high <= t) {
      start = high;
      lower += step + 1u;
      len -= step + 1u;
    } else {
      upperWord = word;
      haveUpper = true;
      len = step;
    }
  }
  if (!haveUpper) upperWord = productStoredWord(first + lower);
  float low = float(upperWord & 0xffffu);
  bool lowBelow = low <= t;
  if (lowBelow) start = low;
  end = lowBelow ? float(upperWord >> 16u) : low;
  return 2u * lower + (lowBelow ? 1u : 0u);
}
// A dispatch of this many samples or more copies the stored table into private memory once and scans it
// there (branch-free selects that vectorise across invocations); one of fewer reads only the entries its
// samples' searches visit (docs/BENCHMARKS.md, "Product strategies").
const uint kProductCopyMinSamples = 32u;
#endif

bool gProductReadStored = false;  // this dispatch samples from the stored table, not a private copy
// A row's quantized running sum up to node j, from the stored or the private table.
float productColumnSum(uint j) {
#ifdef PRODUCT_TABLE_BINDING
  if (gProductReadStored) return productStoredSum(j);
#endif
  return gProductColumnSums[j];
}

float productNodeArea(uint j) {
  vec4 r = productNodeRect(j);
  return (r.z - r.x) * (r.w - r.y);
}

// The direction of the cap (centre, cosRadius) closest to `towards`: the CPU twin is closestDirectionInCap.
vec3 productNodeDirection(vec3 centre, float cosRadius, vec3 towards) {
  float cosAngle = dot(centre, towards);
  if (cosAngle >= cosRadius) return towards;
  vec3 tangent = towards - centre * cosAngle;
  float len = length(tangent);
  if (!(len > 1e-6)) return centre;
  return centre * cosRadius + tangent * (sqrt(max(0.0, 1.0 - cosRadius * cosRadius)) / len);
}

void productBuildTable(Shading s) {
  float sumEF = 0.0;
  vec3 mirror = vec3(-s.woLocal.xy, s.woLocal.z);  // the mirror direction of wo about n, local frame
  [[dont_unroll]] for (uint j = 0u; j < kProductNodes; ++j) {
    float area = productNodeArea(j);
    vec4 centre = productNodeCenter(j);
    vec3 d = normalize(productNodeDirection(toLocal(s, centre.xyz), centre.w, mirror));
    float fCos = 0.0;
    if (area > 0.0 && d.z > 0.0) {
      vec3 f = brdfEval(d, s.woLocal);
      fCos = (f.r + f.g + f.b) / 3.0 * d.z;
      if (!(fCos > 0.0) || isinf(fCos)) fCos = 0.0;  // a non-finite or negative lobe value gives no preference
    }
    gProductColumnSums[j] = area * fCos;
    sumEF += area * fCos;
  }
  float envShare = sumEF > 0.0 && !isinf(sumEF) ? PRODUCT_DEFENSIVE : 1.0;
  float productScale = envShare < 1.0 ? (1.0 - envShare) / sumEF : 0.0;
  // Per row: the weights, their total and count of positive ones, then the row's quantized running sums;
  // the row totals go through the same quantization in gProductRowSums.
  float rowsTotal = 0.0;
  uint positiveRows = 0u;
  [[dont_unroll]] for (uint y = 0u; y < PRODUCT_NODES_Y; ++y) {
    float total = 0.0;
    uint positive = 0u;
    [[dont_unroll]] for (uint x = 0u; x < PRODUCT_NODES_X; ++x) {
      uint j = y * PRODUCT_NODES_X + x;
      float weight = productScale * gProductColumnSums[j] + envShare * productNodeArea(j);
      gProductColumnSums[j] = weight;
      total += weight;
      positive += weight > 0.0 ? 1u : 0u;
    }
    PRODUCT_QUANTIZE(gProductColumnSums, y * PRODUCT_NODES_X, PRODUCT_NODES_X, total, positive)
    gProductRowSums[y] = total;
    rowsTotal += total;
    positiveRows += total > 0.0 ? 1u : 0u;
  }
  PRODUCT_QUANTIZE(gProductRowSums, 0u, PRODUCT_NODES_Y, rowsTotal, positiveRows)
}

void productPrepare(Shading s) {
#ifdef PRODUCT_TABLE_BINDING
  productTableLocate(gl_GlobalInvocationID.xy);
  gProductReadStored = false;
  if (frame.sampleOffset == 0u) {
    productBuildTable(s);
    productTableStore();
  } else {
    gProductReadStored = frame.samplesPerPass < kProductCopyMinSamples;
    productTableLoad(!gProductReadStored);
  }
#else
  productBuildTable(s);
#endif
}

// P(node (x, y)) from the running sums, as sampling chooses it; 0 for an empty node, row or table.
float productNodeProbability(uint x, uint y) {
  float total = gProductRowSums[PRODUCT_NODES_Y - 1u];
  uint base = y * PRODUCT_NODES_X;
  float rowWidth = gProductRowSums[y] - (y == 0u ? 0.0 : gProductRowSums[y - 1u]);
  float columnWidth = productColumnSum(base + x) - (x == 0u ? 0.0 : productColumnSum(base + x - 1u));
  return total > 0.0 ? (rowWidth / total) * (columnWidth / kProductFullScale) : 0.0;
}

#ifdef PRODUCT_UNIFORM_GRID
// h(u) = P(cell of u) / E(cell of u), the head warp's density on the grid.
float productHeadDensity(vec2 u) {
  uvec2 c = productCellOf(u);
  float area = productNodeArea(c.y * PRODUCT_NODES_X + c.x);
  return area > 0.0 ? productNodeProbability(c.x, c.y) / area : 0.0;
}
#endif

vec3 productSample(vec2 u, Shading s, out float pdf, out vec3 radiance) {
  pdf = 0.0;
  radiance = vec3(0.0);
#ifdef IBLX_RECORD_SAMPLES
  gProductChosen.columns = 0u;
#endif
  float total = gProductRowSums[PRODUCT_NODES_Y - 1u];
  if (!(total > 0.0)) return vec3(0.0, 1.0, 0.0);
  // The first row whose running sum exceeds u.y * total: a row of zero width is never chosen.
  float ty = u.y * total;
  uint y = 0u;
  for (uint k = 0u; k + 1u < PRODUCT_NODES_Y; ++k) y += gProductRowSums[k] <= ty ? 1u : 0u;
  float rowStart = y == 0u ? 0.0 : gProductRowSums[y - 1u], rowWidth = gProductRowSums[y] - rowStart;
  uint base = y * PRODUCT_NODES_X;
  float tx = u.x * kProductFullScale;
  uint x = 0u;
  float columnStart, columnWidth;
#ifdef PRODUCT_TABLE_BINDING
  if (gProductReadStored) {
    float columnEnd;
    x = productStoredChoice(y, tx, columnStart, columnEnd);
    columnWidth = columnEnd - columnStart;
  } else
#endif
  {
    for (uint k = 0u; k + 1u < PRODUCT_NODES_X; ++k) x += gProductColumnSums[base + k] <= tx ? 1u : 0u;
    columnStart = x == 0u ? 0.0 : gProductColumnSums[base + x - 1u];
    columnWidth = gProductColumnSums[base + x] - columnStart;
  }
  if (!(rowWidth > 0.0) || !(columnWidth > 0.0)) return vec3(0.0, 1.0, 0.0);  // u on a float edge
  vec2 v = clamp(vec2((tx - columnStart) / columnWidth, (ty - rowStart) / rowWidth), vec2(0.0),
                 vec2(kOneMinusEpsilon));
  uint j = base + x;
  vec4 r = productNodeRect(j);
  // Inside the node's rectangle, a float set: at most one float step below its upper edges (which are > 0).
  vec2 below = uintBitsToFloat(floatBitsToUint(r.zw) - 1u);
  vec2 inNode = clamp(r.xy + v * (r.zw - r.xy), r.xy, below);
  float envDensity;
  vec3 wi = envSample(inNode, s.n, envDensity, radiance);
  float area = (r.z - r.x) * (r.w - r.y);
  // P(j) as productNodeProbability computes it, from the widths found above.
  float probability = (rowWidth / total) * (columnWidth / kProductFullScale);
  pdf = envDensity > 0.0 && area > 0.0 ? probability / area * envDensity : 0.0;
#ifdef IBLX_RECORD_SAMPLES
  gProductChosen = ProductChoice(j, PRODUCT_NODES_X, PRODUCT_NODES_Y, probability, productNodeMapUv(j));
#endif
#ifdef PRODUCT_TAIL_ENV_OT
  // A split sun's texel: the branch taken (the sun row when u.y reached it, env-ot's row search) keeps the
  // chosen cell's density, the other branch's preimage is located.
  ivec2 texel = directionToTexel(wi);
  vec2 q = envOtBranchPdfs(texel);
  if (pdf > 0.0 && q.y > 0.0) {
    bool sunRow = inNode.y >= tableFloat(envOtRowCdf, ENV_OT_GRID);
    vec2 uMap, uSun;
    bool hasMap, hasSun;
    envOtPreimages(wi, texel, uMap, hasMap, uSun, hasSun);
    float head = probability / area;
    float other = sunRow ? (hasMap ? productHeadDensity(uMap) * q.x : 0.0)
                         : (hasSun ? productHeadDensity(uSun) * q.y : 0.0);
    pdf = head * (sunRow ? q.y : q.x) + other;
  }
#endif
  return wi;
}

#ifdef PRODUCT_TAIL_ENV_OT
// h(u_map) q_map + h(u_sun) q_sun (engine/sampling/product/env_ot_product.h).
float productPdf(vec3 wi, Shading s) {
  ivec2 texel = directionToTexel(wi);
  vec2 q = envOtBranchPdfs(texel);
  vec2 uMap, uSun;
  bool hasMap, hasSun;
  envOtPreimages(wi, texel, uMap, hasMap, uSun, hasSun);
  return (hasMap && q.x > 0.0 ? productHeadDensity(uMap) * q.x : 0.0) +
         (hasSun && q.y > 0.0 ? productHeadDensity(uSun) * q.y : 0.0);
}
#else
float productPdf(vec3 wi, Shading s) {
  uvec2 node = productNodeOf(wi);
  if (node.x >= PRODUCT_NODES_X || node.y >= PRODUCT_NODES_Y) return 0.0;
  float area = productNodeArea(node.y * PRODUCT_NODES_X + node.x);
  return area > 0.0 ? productNodeProbability(node.x, node.y) / area * envPdf(wi, s.n) : 0.0;
}
#endif
#endif
