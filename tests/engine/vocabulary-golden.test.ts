/*
 * The vocabulary scene (determinism-fixtures.ts buildVocabularyScene: compound dumbbells with
 * off-origin circles, capsules, rounded and decomposed polygons, segments, a chain, filters,
 * sensors, surfaces, events and queries) gives its pinned hashes in Node. The browser test
 * (tests/browser/engine-determinism.test.ts) checks Chromium and Firefox give Node's; this pins
 * Node's, so a change in what these shapes do is seen by the engine tests alone.
 */
import { describe, expect, it } from 'vitest'
import { hex, runVocabulary, VOCABULARY_GOLDEN } from './determinism-fixtures.ts'

describe('the vocabulary scene', () => {
  it('matches its pinned world and stream hashes at every 500th step', () => {
    const actual = runVocabulary().map(hex)
    expect(actual, `set VOCABULARY_GOLDEN to [${actual.join(', ')}] if intended`).toEqual(
      VOCABULARY_GOLDEN.map(hex),
    )
  })
})
