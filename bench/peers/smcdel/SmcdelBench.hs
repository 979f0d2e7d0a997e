{- | SMCDEL's side of bench/symbolic.py --fresh-process --smcdel-bin (issue 23).

One puzzle per process:

>  smcdel-bench [--warm] (muddy N | drinking N | dining N | dining-impl-outside N | sap | manager)

prints one JSON line {"puzzle", "n", "cpu", "ok", "answer"}.  "cpu" is System.CPUTime.getCPUTime
(process CPU time, user + system, GC included) around building SMCDEL's structure, building the formula
and evaluating it with SMCDEL.Symbolic.S5 (CacBDD); the first BDD call (CacBDD's manager set-up) falls
inside; with --warm a first BDD operation creates the manager before the clock starts, and `manager`
times that operation alone.  "ok" compares the result with the literature answer after the clock has stopped.

The structures and formulas are SMCDEL's own (its example modules); this file only sequences them the way
bench/symbolic.py sequences delkit's calls:

* muddy N: SMCDEL.Examples.MuddyChildren's mudScnInit N N, father N and knows i.  The protocol of
  delkit.symbolic.muddy_symbolic: announce the father's formula, then per round evaluate every child's
  "knows whether I am muddy" at the actual state and announce the conjunction of the truthful answers,
  until all know.  Announcements are SMCDEL's unsafeUpdate (θ ∧ ||ψ||, what delkit's announce does);
  SMCDEL's checked update would evaluate ψ once more at the actual state.
* drinking N: SMCDEL.Examples.DrinkLogic.thirstyCheck N (thirstyF at thirstyScene).
* dining N: SMCDEL's bench/diningcrypto.hs formula (written out here: the bench module is not part of the
  library) on SMCDEL.Examples.DiningCrypto.genDcKnsInit N (complete graph), validViaBdd.
  dining-impl-outside N: the same with ¬P1 → outside the announcement, as delkit.puzzles.dining writes it.
* sap: SMCDEL.Examples.SumAndProduct.sapSolutions (structure and formula are top-level constants,
  first forced inside the clock).
-}
module Main (main) where

import Control.Exception (evaluate)
import Data.List (isPrefixOf)
import System.CPUTime (getCPUTime)
import System.Environment (getArgs)
import System.Exit (exitWith, ExitCode(ExitFailure))
import System.IO (hPutStrLn, stderr)
import Text.Printf (printf)
import Text.Read (readMaybe)

import SMCDEL.Language
import SMCDEL.Symbolic.S5
import SMCDEL.Examples.MuddyChildren (mudScnInit, father, knows)
import SMCDEL.Examples.DrinkLogic (thirstyCheck)
import SMCDEL.Examples.DiningCrypto (genDcKnsInit, genDcReveal)
import SMCDEL.Examples.SumAndProduct (sapSolutions, sapExplainState)

-- | (rounds in which nobody knew, round in which all children knew): the literature answer for N
-- muddy children out of N is (N-1, N).
muddy :: Int -> (Int, Int)
muddy n = go 1 0 (unsafeUpdate (mudScnInit n n) (father n) :: KnowScene) where
  go :: Int -> Int -> KnowScene -> (Int, Int)
  go rnd nobody scn
    | and key = (nobody, rnd)
    | rnd > n + 2 = error "muddy children: no answer after N+2 rounds"
    | otherwise = nobody' `seq` go (rnd + 1) nobody' (unsafeUpdate scn said)
    where
      key = [ evalViaBdd scn (knows i) | i <- [1..n] ]
      nobody' = if or key then nobody else nobody + 1
      said = Conj [ if k then knows i else Neg (knows i) | (i, k) <- zip [1..n] key ]

-- | bench/diningcrypto.hs's benchDcCheckForm: announce whether the XOR of all revealed bits holds, then
-- if 1 did not pay, 1 knows nobody paid or knows one of 2..n paid without knowing who.
diningForm :: Bool -> Int -> Form
diningForm implOutside n
  | implOutside = Impl (Neg (PrpF (P 1))) (PubAnnounceW reveal after)
  | otherwise = PubAnnounceW reveal (Impl (Neg (PrpF (P 1))) after)
  where
    reveal = Xor [ genDcReveal n i | i <- [1..n] ]
    after = Disj [ K "1" (Conj [ Neg (PrpF (P k)) | k <- [1..n] ])
                 , Conj [ K "1" (Disj [ PrpF (P k) | k <- [2..n] ])
                        , Conj [ Neg (K "1" (PrpF (P k))) | k <- [2..n] ] ] ]

timed :: IO a -> IO (Double, a)
timed act = do
  t0 <- getCPUTime
  x <- act
  t1 <- getCPUTime
  return (fromIntegral (t1 - t0) / 1e12, x)

report :: String -> Int -> Double -> Bool -> String -> IO ()
report name n cpu ok answer =
  printf "{\"puzzle\": \"%s\", \"n\": %d, \"cpu\": %.6f, \"ok\": %s, \"answer\": \"%s\"}\n"
    name n cpu (if ok then "true" else "false") (concatMap esc answer)
  where esc c = if c `elem` "\"\\" then ['\\', c] else [c]

usage :: String -> IO a
usage why = do
  hPutStrLn stderr $ "smcdel-bench: " ++ why
    ++ "; usage: smcdel-bench [--warm] (muddy N | drinking N | dining N | dining-impl-outside N | sap | manager), N a whole number >= 2"
  exitWith (ExitFailure 2)

-- | Force CacBDD's manager (HasCacBDD creates it on the first BDD operation): one comparison of two
-- constant BDDs.
touchManager :: IO Bool
touchManager = evaluate (boolBddOf Top == boolBddOf Top)

main :: IO ()
main = do
  argv <- getArgs
  args <- case argv of
    ("--warm" : rest) -> touchManager >> return rest
    _ -> return argv
  case args of
    ["manager"] -> do
      (cpu, ok) <- timed touchManager
      report "manager" 0 cpu ok "CacBDD manager created (first BDD operation)"
    ["sap"] -> do
      (cpu, sols) <- timed (let s = sapSolutions in evaluate (length (concat s)) >> return s)
      let answer = unwords (map sapExplainState sols)
      report "sap" 100 cpu (length sols == 1 && "x = 4, y = 13," `isPrefixOf` answer) answer
    [name, arg] -> do
      n <- maybe (usage $ "N must be a whole number, got " ++ show arg) return (readMaybe arg)
      if n < 2 then usage ("N must be at least 2, got " ++ show n) else return ()
      case name of
        "muddy" -> do
          (cpu, (nobody, known)) <- timed (let r@(a, b) = muddy n in evaluate a >> evaluate b >> return r)
          report name n cpu (nobody == n - 1 && known == n)
            (printf "nobody knows in %d rounds, all know in round %d" nobody known)
        "drinking" -> do
          (cpu, ok) <- timed (evaluate (thirstyCheck n))
          report name n cpu ok (if ok then "thirstyF holds" else "thirstyF fails")
        _ | name `elem` ["dining", "dining-impl-outside"] -> do
          (cpu, ok) <- timed (evaluate (validViaBdd (genDcKnsInit n) (diningForm (name /= "dining") n)))
          report name n cpu ok (if ok then "valid" else "not valid")
        _ -> usage ("unknown puzzle " ++ show name)
    _ -> usage "expected a puzzle and N"
