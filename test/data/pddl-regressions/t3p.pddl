(define (problem t3p) (:domain t3) (:objects r a b - node) (:init (edge r a) (edge r b) (edge a b) (leaf b)) (:goal (done)))
