// Strategy "product-mis": two-sample MIS (Veach 1997, §9.2.2, n = 1 each) of the product technique
// (lib/product_sampling.glsl) and the BRDF technique, balance or power heuristic: each sample draws one direction
// from each, from dimension pairs 0 and 1, and adds both weighted estimates. The BRDF technique covers what the
// product's per-node lobe values miss (lobes narrower than a node).
#include "lib/mis_weights.glsl"
#include "lib/product_sampling.glsl"
#include "lib/sample_record.glsl"

void prepareStrategy(Shading s) { productPrepare(s); }

vec3 estimateRadiance(SamplePoint p, Shading s) {
  bool power = frame.strategy.y > 0.5;
  vec2 uProduct = samplePair(p, 0u), uBrdf = samplePair(p, 1u);
  float pProductP, pBrdfB;
  vec3 radianceP;
  vec3 wiP = productSample(uProduct, s, pProductP, radianceP);
  vec3 wiLocalB = brdfSample(uBrdf, s.woLocal, pBrdfB);
  vec3 wiB = normalize(toWorld(s, wiLocalB));
  vec3 wiLocalP = toLocal(s, wiP);
  float pBrdfP = brdfPdf(wiLocalP, s.woLocal);  // the other technique's density at each direction
  float pProductB = productPdf(wiB, s);
  vec3 radianceB = envRadiance(wiB);
  float weightOverPdfP, weightOverPdfB;
  vec3 weightP = misWeight(wiLocalP, s, pProductP, pBrdfP, power, weightOverPdfP);
  vec3 weightB = misWeight(wiLocalB, s, pBrdfB, pProductB, power, weightOverPdfB);
  RECORD_DRAW(0u, kSampleTechniqueProduct, uProduct, wiP, pProductP);
  RECORD_PRODUCT_NODE(0u);
  if (misContributes(wiLocalP, pProductP)) RECORD_WEIGHT(0u, weightOverPdfP * pProductP, weightP, radianceP);
  RECORD_DRAW(1u, kSampleTechniqueBrdf, uBrdf, wiB, pBrdfB);
  if (misContributes(wiLocalB, pBrdfB)) RECORD_WEIGHT(1u, weightOverPdfB * pBrdfB, weightB, radianceB);
  return radianceP * weightP + radianceB * weightB;
}
