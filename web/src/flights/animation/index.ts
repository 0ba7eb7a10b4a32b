// The flight animation layer: `new TrafficAnimation(map, datasetId, opts)` (types.ts documents the API).
export { TrafficAnimation, MAX_TAIL_SECONDS } from './trafficAnimation';
export { legendOf, RAMPS, PALETTE } from './colors';
export { decodeTsan, TSAN_MIME, type TsanChunk } from './tsan';
export type * from './types';
