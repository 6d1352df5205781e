/*
 * Rooms: the networking around one RoomSimulation (inputs, snapshots per client, the lockstep
 * feed), players and their connections, the room manager that creates rooms by name, where rooms
 * run (room-host.ts) and the fixed-step tick clock.
 */
export { DROP_CONNECTION, type PlayerConnection } from './player-connection.ts'
export type { Room } from './room.ts'
export { type JoinRequest, LocalRoomHost, type RoomHost, type RoomSeat, roomSummary } from './room-host.ts'
export { RoomManager } from './room-manager.ts'
export { handleRoomMessage, type RoomMessage, type Strike } from './room-messages.ts'
export type { RoomPlayer } from './room-player.ts'
export { phaseAccumulator } from './tick-clock.ts'
