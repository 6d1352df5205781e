/*
 * Ball drop: the tutorial game of docs/games.md (players drop balls; one at rest on the target
 * scores for its dropper).
 */
export { type BallDropState, ballDrop } from './ball-drop-game.ts'
