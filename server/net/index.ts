/*
 * The WebSocket transport: upgrades, one ClientSession per socket, the join flow from `join` to a
 * seat in a room, and the policy for clients that break the rules (strikes, rates, drops).
 */
export type { ClientSession } from './client-session.ts'
export { Transport } from './transport.ts'
