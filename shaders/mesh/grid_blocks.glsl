// A density grid sampled block by block (src/nerf/mesh/sample_blocks.h): slot s of the listed
// blocks is sample (s % 64) of block blocks[s / 64], x fastest within the 4^3 block.
const uint kBlockSide = 4u;  // nerf::kBlockSide

// The grid index of slot `slot` in block `block`; false past the grid's last sample.
bool blockSample(uint block, uint slot, uvec3 n, uvec3 blockCount, out uvec3 idx) {
  uvec3 b = uvec3(block % blockCount.x, (block / blockCount.x) % blockCount.y, block / (blockCount.x * blockCount.y));
  uint l = slot % (kBlockSide * kBlockSide * kBlockSide);
  idx = b * kBlockSide + uvec3(l % kBlockSide, (l / kBlockSide) % kBlockSide, l / (kBlockSide * kBlockSide));
  return all(lessThan(idx, n));
}
