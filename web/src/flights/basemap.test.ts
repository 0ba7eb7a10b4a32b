import { describe, expect, it } from 'vitest';
import { splitAtAntimeridian, unwrapPolygons } from './basemap';

describe('antimeridian handling', () => {
  it('splits a line where it jumps from +180 to -180', () => {
    const g = splitAtAntimeridian({
      type: 'MultiLineString',
      coordinates: [
        [
          [170, 65],
          [180, 66],
          [-180, 66],
          [-170, 65],
        ],
        [
          [0, 0],
          [1, 1],
        ],
      ],
    });
    expect(g.coordinates).toEqual([
      [
        [170, 65],
        [180, 66],
      ],
      [
        [-180, 66],
        [-170, 65],
      ],
      [
        [0, 0],
        [1, 1],
      ],
    ]);
  });

  it('shifts the western part of a crossing ring by 360°', () => {
    const ring = [
      [170, 60],
      [-170, 60],
      [-170, 70],
      [170, 70],
      [170, 60],
    ];
    const g = unwrapPolygons({ type: 'Polygon', coordinates: [ring] });
    expect(g).toEqual({
      type: 'Polygon',
      coordinates: [
        [
          [170, 60],
          [190, 60],
          [190, 70],
          [170, 70],
          [170, 60],
        ],
      ],
    });
  });

  it('leaves polar rings and ordinary rings alone', () => {
    const polar = [
      [-180, -80],
      [180, -80],
      [180, -90],
      [-180, -90],
      [-180, -80],
    ];
    const plain = [
      [0, 0],
      [1, 0],
      [1, 1],
      [0, 0],
    ];
    const g = { type: 'MultiPolygon' as const, coordinates: [[polar], [plain]] };
    expect(unwrapPolygons(g)).toEqual(g);
  });
});
