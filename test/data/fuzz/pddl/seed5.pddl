; Miconic (IPC 2000, STRIPS track), untyped: an elevator boards and departs passengers.
(define (domain miconic)
  (:requirements :strips)
  (:predicates (origin ?person ?floor) (floor ?floor) (passenger ?passenger) (destin ?person ?floor)
               (above ?floor1 ?floor2) (boarded ?person) (served ?person) (lift-at ?floor))
  (:action board
    :parameters (?f ?p)
    :precondition (and (floor ?f) (passenger ?p) (lift-at ?f) (origin ?p ?f))
    :effect (boarded ?p))
  (:action depart
    :parameters (?f ?p)
    :precondition (and (floor ?f) (passenger ?p) (lift-at ?f) (destin ?p ?f) (boarded ?p))
    :effect (and (not (boarded ?p)) (served ?p)))
  (:action up
    :parameters (?f1 ?f2)
    :precondition (and (floor ?f1) (floor ?f2) (lift-at ?f1) (above ?f1 ?f2))
    :effect (and (lift-at ?f2) (not (lift-at ?f1))))
  (:action down
    :parameters (?f1 ?f2)
    :precondition (and (floor ?f1) (floor ?f2) (lift-at ?f1) (above ?f2 ?f1))
    :effect (and (lift-at ?f2) (not (lift-at ?f1)))))

;;;;
(define (problem miconic-3-2-1)
  (:domain miconic)
  (:objects f0 f1 f2 p0 p1)
  (:init (floor f0) (floor f1) (floor f2) (passenger p0) (passenger p1) (above f0 f1) (above f0 f2) (above f1 f2) (origin p0 f0) (destin p0 f2) (origin p1 f1) (destin p1 f0) (lift-at f0))
  (:goal (and (served p0) (served p1))))
