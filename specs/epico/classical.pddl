; e-PICO classical level (seed 004, Listing 5): one arm's block world with stack positions, in PDDL (STRIPS
; with typing). planners/classical.py solves the same domain (its ASP twin with clingo, or its own
; breadth-first search, the default); tests check that pyperplan's breadth-first search on this file finds
; plans of the same (optimal) length. Problems: planners.classical.to_pddl(state, goal).
;
; Objects: blocks, stacks s0..s2 of the acting robot, a base (table) per stack, levels l0..lN.
;   (on ?b ?u)      block ?b lies on block or base ?u
;   (at ?b ?s ?l)   block ?b is in stack ?s at level ?l
;   (top ?s ?u)     ?u (a block or the stack's base) is the top of stack ?s
;   (above ?u ?l)   a block put on ?u lands at level ?l
;   (barrier-free) / (on-barrier ?b)   the shared table (capacity one)
;   (in-stacks ?b)  ?b lies in one of the robot's stacks
(define (domain epico-arm)
  (:requirements :strips :typing)
  (:types thing stack level - object block base - thing)
  (:predicates (on ?b - block ?u - thing) (at ?b - block ?s - stack ?l - level) (top ?s - stack ?u - thing)
               (above ?u - thing ?l - level) (succ ?l ?l2 - level) (holding ?b - block) (handempty)
               (barrier-free) (on-barrier ?b - block) (in-stacks ?b - block))

  ; pick(block, on, level, stack)
  (:action pick
    :parameters (?b - block ?u - thing ?l - level ?s - stack)
    :precondition (and (handempty) (top ?s ?b) (on ?b ?u) (at ?b ?s ?l))
    :effect (and (holding ?b) (not (handempty)) (not (top ?s ?b)) (top ?s ?u) (not (on ?b ?u))
                 (not (at ?b ?s ?l)) (not (above ?b ?l)) (not (in-stacks ?b))))

  ; place(block, onto, level, stack)
  (:action place
    :parameters (?b - block ?u - thing ?l - level ?s - stack ?l2 - level)
    :precondition (and (holding ?b) (top ?s ?u) (above ?u ?l) (succ ?l ?l2))
    :effect (and (handempty) (not (holding ?b)) (on ?b ?u) (at ?b ?s ?l) (top ?s ?b) (not (top ?s ?u))
                 (above ?b ?l2) (in-stacks ?b)))

  ; put_on_barrier(block)
  (:action put_on_barrier
    :parameters (?b - block)
    :precondition (and (holding ?b) (barrier-free))
    :effect (and (handempty) (not (holding ?b)) (on-barrier ?b) (not (barrier-free))))

  ; take_from_barrier(block)
  (:action take_from_barrier
    :parameters (?b - block)
    :precondition (and (handempty) (on-barrier ?b))
    :effect (and (holding ?b) (not (handempty)) (not (on-barrier ?b)) (barrier-free)))
)
